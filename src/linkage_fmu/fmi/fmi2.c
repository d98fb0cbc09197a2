/* FMI 2.0 co-simulation framework of linkage_fmu's FMUs.
 *
 * An FMU's binary is this file compiled with a generated `config.h` (the model's
 * identifier, GUID and variable table) and one backend, included below as BACKEND:
 * `backend_pythonfmu.c` (pythonfmu's stock wrapper, shipped beside the binary) or
 * `backend_native.c` (the linkage's generated C kernels). The framework owns what every
 * flavour must do the same way, and hands a backend only calls that are valid:
 *
 * - every argument is checked before any state changes: null pointers, unknown value
 *   references, wrong types, variables that may not be set in the current state (fixed
 *   parameters after initialisation, outputs), strings that are not UTF-8, booleans
 *   that are neither true nor false, step sizes and times that are not finite and
 *   positive; a bad call is fmi2Error with a log naming the call, the reference and the
 *   reason, and the instance stays usable;
 * - the co-simulation state machine of FMI 2.0; an exitInitializationMode that the
 *   backend rejects (an invalid parameter set) leaves the instance in initialisation
 *   mode, to be fixed;
 * - fmi2Fatal never reaches the host: a backend that reports it marks the instance
 *   failed, which answers fmi2Error from then on;
 * - fmi2GetBooleanStatus(fmi2Terminated) (true after a discarded step, until a step
 *   succeeds) and fmi2GetRealStatus(fmi2LastSuccessfulTime);
 * - serialized states carry a header (model identifier, GUID, format version, length,
 *   CRC-32): a foreign or corrupted state is rejected with fmi2Error;
 * - the GUID passed to fmi2Instantiate must match.
 *
 * No global state but what is constant per process (the backend's loaded library).
 */
#define _GNU_SOURCE /* dladdr */
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"

enum { T_REAL, T_INTEGER, T_BOOLEAN, T_STRING };
/* what a variable is, for the FMI 2 rules on setting it */
enum { K_INPUT, K_FIXED, K_TUNABLE, K_OUTPUT, K_OTHER };

typedef struct {
    int type;
    int kind;
    const char *name;
    int role;  /* what the backend makes of it (backend_native.c), and its position there */
    int index;
} Variable;

#include "config.h"
#include "fmi_common.h"


typedef enum { S_INSTANTIATED, S_INIT, S_STEP, S_TERMINATED, S_FAILED } Machine;
static const char *MACHINE_NAMES[] = {"Instantiated", "InitializationMode", "StepComplete",
                                      "Terminated", "failed"};

typedef struct Instance {
    char *name;
    fmi2CallbackFunctions host; /* the importer's callbacks */
    void *model;                /* the backend's */
    Machine machine;
    fmi2Boolean logging;
    unsigned categories; /* bit i: LOG_CATEGORIES[i] enabled; 0 = all */
    double time;         /* the last successful communication point */
    fmi2Boolean discarded; /* the last step was discarded: fmi2Terminated answers true */
} Instance;

typedef struct {
    char magic[8];
    const char *guid;
    double time;
    void *model;
} SavedState;


static int category_enabled(const Instance *in, fmi2Status status, const char *category) {
    if (status >= fmi2Error) return 1; /* errors are always reported */
    if (!in->logging) return 0;
    if (!in->categories) return 1;
    for (unsigned i = 0; i < N_CATEGORIES; i++)
        if ((in->categories >> i & 1u) &&
            (!strcmp(LOG_CATEGORIES[i], "logAll") ||
             (category && !strcmp(category, LOG_CATEGORIES[i]))))
            return 1;
    return 0;
}

/* Hosts treat the message as a printf format, and hosts written with ctypes (fmpy)
 * cannot format at all: pass the final text with '%' doubled and no arguments. */
static void emit(const Instance *in, fmi2Status status, const char *category,
                 const char *message) {
    if (!in->host.logger || !category_enabled(in, status, category)) return;
    char text[2048];
    size_t n = 0;
    for (const char *p = message; *p && n + 2 < sizeof text; p++) {
        if (*p == '%') text[n++] = '%';
        text[n++] = *p;
    }
    text[n] = '\0';
    in->host.logger(in->host.componentEnvironment, in->name, status, category, text);
}

static const char *status_category(fmi2Status status) {
    return status >= fmi2Error ? "logStatusError"
           : status == fmi2Discard ? "logStatusDiscard"
                                   : "logStatusWarning";
}

/* Log a message (printf-style) with `status`, and return `status`. */
static fmi2Status say(const Instance *in, fmi2Status status, const char *fmt, ...) {
    char text[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    emit(in, status, status_category(status), text);
    return status;
}


/* The backend: BACKEND defines the functions declared here (static: one translation
 * unit), each called only with checked arguments in a state that allows the call. */
static int backend_ready(char *why, size_t size);
static void *backend_instantiate(Instance *in, fmi2String guid, fmi2String resources,
                                 fmi2Boolean visible);
static void backend_free(Instance *in);
static fmi2Status backend_setup_experiment(Instance *in, fmi2Boolean tolerance_defined,
                                           fmi2Real tolerance, fmi2Real start,
                                           fmi2Boolean stop_defined, fmi2Real stop);
static fmi2Status backend_enter_initialization(Instance *in);
static fmi2Status backend_exit_initialization(Instance *in);
static fmi2Status backend_terminate(Instance *in);
static fmi2Status backend_reset(Instance *in);
static fmi2Status backend_get_real(Instance *in, const fmi2ValueReference vr[], size_t n,
                                   fmi2Real value[]);
static fmi2Status backend_get_integer(Instance *in, const fmi2ValueReference vr[], size_t n,
                                      fmi2Integer value[]);
static fmi2Status backend_get_boolean(Instance *in, const fmi2ValueReference vr[], size_t n,
                                      fmi2Boolean value[]);
static fmi2Status backend_get_string(Instance *in, const fmi2ValueReference vr[], size_t n,
                                     fmi2String value[]);
static fmi2Status backend_set_real(Instance *in, const fmi2ValueReference vr[], size_t n,
                                   const fmi2Real value[]);
static fmi2Status backend_set_integer(Instance *in, const fmi2ValueReference vr[], size_t n,
                                      const fmi2Integer value[]);
static fmi2Status backend_set_boolean(Instance *in, const fmi2ValueReference vr[], size_t n,
                                      const fmi2Boolean value[]);
static fmi2Status backend_set_string(Instance *in, const fmi2ValueReference vr[], size_t n,
                                     const fmi2String value[]);
static fmi2Status backend_do_step(Instance *in, fmi2Real t, fmi2Real h, fmi2Boolean no_set);
static fmi2Status backend_get_state(Instance *in, void **state); /* *state: NULL or reused */
static fmi2Status backend_set_state(Instance *in, void *state);
static void backend_free_state(Instance *in, void *state);
static fmi2Status backend_state_size(Instance *in, void *state, size_t *size);
static fmi2Status backend_serialize(Instance *in, void *state, unsigned char *bytes, size_t n);
static fmi2Status backend_deserialize(Instance *in, const unsigned char *bytes, size_t n,
                                      void **state);

#include BACKEND

/* Check the instance pointer; NULL means no instance to log through. */
#define INSTANCE(c, call)                                                                  \
    Instance *in = (Instance *)(c);                                                        \
    if (!in) return fmi2Error;                                                             \
    if (in->machine == S_FAILED)                                                           \
        return say(in, fmi2Error, call ": this instance failed earlier and can only be freed");

static fmi2Status require(const Instance *in, const char *call, unsigned allowed) {
    if (allowed >> in->machine & 1u) return fmi2OK;
    return say(in, fmi2Error, "%s is not allowed in state %s", call,
               MACHINE_NAMES[in->machine]);
}
#define IN(s) (1u << (s))

/* A backend's answer: fmi2Fatal fails the instance for good, fmi2Pending is an error. */
static fmi2Status answer(Instance *in, const char *call, fmi2Status status) {
    if (status == fmi2Fatal) {
        in->machine = S_FAILED;
        return say(in, fmi2Error, "%s failed fatally; this instance can only be freed", call);
    }
    return status == fmi2Pending ? fmi2Error : status;
}

/* -- argument checks -------------------------------------------------------------------- */
static const char *TYPE_NAMES[] = {"Real", "Integer", "Boolean", "String"};

static fmi2Status check_refs(const Instance *in, const char *call, const fmi2ValueReference vr[],
                             size_t nvr, const void *values, int type) {
    if (nvr == 0) return fmi2OK;
    if (!vr || !values)
        return say(in, fmi2Error, "%s: %s is NULL with nvr = %zu", call,
                   !vr ? "the value reference array" : "the value array", nvr);
    for (size_t i = 0; i < nvr; i++) {
        if (vr[i] >= N_VARIABLES || !VARIABLES[vr[i]].name)
            return say(in, fmi2Error, "%s: value reference %u (entry %zu) is not a variable of "
                       MODEL_IDENTIFIER, call, (unsigned)vr[i], i);
        if (VARIABLES[vr[i]].type != type)
            return say(in, fmi2Error, "%s: value reference %u ('%s') is a %s, not a %s", call,
                       (unsigned)vr[i], VARIABLES[vr[i]].name,
                       TYPE_NAMES[VARIABLES[vr[i]].type], TYPE_NAMES[type]);
    }
    return fmi2OK;
}

static fmi2Status check_settable(const Instance *in, const char *call,
                                 const fmi2ValueReference vr[], size_t nvr) {
    for (size_t i = 0; i < nvr; i++) {
        const Variable *v = &VARIABLES[vr[i]];
        if (v->kind == K_INPUT || v->kind == K_TUNABLE) continue;
        if (v->kind == K_FIXED && (in->machine == S_INSTANTIATED || in->machine == S_INIT))
            continue;
        return say(in, fmi2Error, "%s: '%s' (value reference %u) %s", call, v->name,
                   (unsigned)vr[i],
                   v->kind == K_FIXED ? "is a fixed parameter: it can only be set before "
                                        "exitInitializationMode"
                                      : "is an output: it cannot be set");
    }
    return fmi2OK;
}

/* -- FMI 2.0: inquiry, instances, logging ------------------------------------------------ */
const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation,
                              const fmi2CallbackFunctions *functions, fmi2Boolean visible,
                              fmi2Boolean loggingOn) {
    if (!functions || !functions->allocateMemory || !functions->freeMemory) return NULL;
    Instance probe = {0};
    probe.name = (char *)(instanceName && *instanceName ? instanceName : "?");
    probe.host = *functions;
    probe.logging = loggingOn;
    char why[PATH_MAX + 1024];
    why[0] = '\0';
    if (!instanceName || !*instanceName)
        snprintf(why, sizeof why, "the instance name is empty");
    else if (fmuType != fmi2CoSimulation)
        snprintf(why, sizeof why, MODEL_IDENTIFIER " supports co-simulation only");
    else if (!fmuGUID || strcmp(fmuGUID, MODEL_GUID))
        snprintf(why, sizeof why, "GUID %s does not match this FMU's " MODEL_GUID
                 " (a modelDescription.xml of another FMU?)", fmuGUID ? fmuGUID : "(null)");
    else if (!fmuResourceLocation || strncmp(fmuResourceLocation, "file:", 5))
        snprintf(why, sizeof why, "the resource location must be a file: URI, got %s",
                 fmuResourceLocation ? fmuResourceLocation : "(null)");
    else
        backend_ready(why, sizeof why);
    if (why[0]) {
        say(&probe, fmi2Error, "fmi2Instantiate: %s", why);
        return NULL;
    }
    Instance *in = (Instance *)functions->allocateMemory(1, sizeof *in);
    char *name = (char *)functions->allocateMemory(strlen(instanceName) + 1, 1);
    if (!in || !name) {
        if (in) functions->freeMemory(in);
        if (name) functions->freeMemory(name);
        say(&probe, fmi2Error, "fmi2Instantiate: out of memory");
        return NULL;
    }
    strcpy(name, instanceName);
    *in = probe;
    in->name = name;
    in->machine = S_INSTANTIATED;
    in->model = backend_instantiate(in, fmuGUID, fmuResourceLocation, visible);
    if (!in->model) {
        functions->freeMemory(name);
        functions->freeMemory(in);
        return NULL;
    }
    return in;
}

void fmi2FreeInstance(fmi2Component c) {
    Instance *in = (Instance *)c;
    if (!in) return;
    backend_free(in);
    fmi2CallbackFreeMemory release = in->host.freeMemory;
    release(in->name);
    release(in);
}

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean loggingOn, size_t nCategories,
                               const fmi2String categories[]) {
    INSTANCE(c, "fmi2SetDebugLogging");
    if (nCategories && !categories)
        return say(in, fmi2Error, "fmi2SetDebugLogging: categories is NULL with nCategories = %zu",
                   nCategories);
    unsigned mask = 0;
    for (size_t i = 0; i < nCategories; i++) {
        unsigned k = 0;
        while (k < N_CATEGORIES && !(categories[i] && !strcmp(categories[i], LOG_CATEGORIES[k])))
            k++;
        if (k == N_CATEGORIES)
            return say(in, fmi2Error, "fmi2SetDebugLogging: unknown log category '%s'; the "
                       "categories are logStatusWarning, logStatusDiscard, logStatusError, "
                       "logStatusFatal, logAll", categories[i] ? categories[i] : "(null)");
        mask |= 1u << k;
    }
    in->logging = loggingOn;
    in->categories = mask;
    return fmi2OK;
}

/* -- life cycle ------------------------------------------------------------------------- */
fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                               fmi2Real startTime, fmi2Boolean stopTimeDefined,
                               fmi2Real stopTime) {
    INSTANCE(c, "fmi2SetupExperiment");
    if (require(in, "fmi2SetupExperiment", IN(S_INSTANTIATED))) return fmi2Error;
    if (!isfinite(startTime))
        return say(in, fmi2Error, "fmi2SetupExperiment: startTime = %g is not finite", startTime);
    if (stopTimeDefined && !(stopTime >= startTime))
        return say(in, fmi2Error, "fmi2SetupExperiment: stopTime = %g is not >= startTime = %g",
                   stopTime, startTime);
    if (toleranceDefined && !(tolerance > 0.0 && isfinite(tolerance)))
        return say(in, fmi2Error, "fmi2SetupExperiment: tolerance = %g is not a positive number",
                   tolerance);
    fmi2Status s = answer(in, "fmi2SetupExperiment",
                          backend_setup_experiment(in, toleranceDefined, tolerance, startTime,
                                                   stopTimeDefined, stopTime));
    if (s <= fmi2Warning) in->time = startTime;
    return s;
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c) {
    INSTANCE(c, "fmi2EnterInitializationMode");
    if (require(in, "fmi2EnterInitializationMode", IN(S_INSTANTIATED))) return fmi2Error;
    fmi2Status s = answer(in, "fmi2EnterInitializationMode", backend_enter_initialization(in));
    if (s <= fmi2Warning) in->machine = S_INIT;
    return s;
}

fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
    INSTANCE(c, "fmi2ExitInitializationMode");
    if (require(in, "fmi2ExitInitializationMode", IN(S_INIT))) return fmi2Error;
    fmi2Status s = answer(in, "fmi2ExitInitializationMode", backend_exit_initialization(in));
    /* an invalid parameter set leaves the instance in initialisation mode, to be fixed */
    if (s <= fmi2Warning) in->machine = S_STEP;
    return s;
}

fmi2Status fmi2Terminate(fmi2Component c) {
    INSTANCE(c, "fmi2Terminate");
    if (require(in, "fmi2Terminate", IN(S_STEP))) return fmi2Error;
    fmi2Status s = answer(in, "fmi2Terminate", backend_terminate(in));
    if (s <= fmi2Warning) in->machine = S_TERMINATED;
    return s;
}

fmi2Status fmi2Reset(fmi2Component c) {
    INSTANCE(c, "fmi2Reset");
    fmi2Status s = answer(in, "fmi2Reset", backend_reset(in));
    if (s <= fmi2Warning) {
        in->machine = S_INSTANTIATED;
        in->time = 0.0;
        in->discarded = fmi2False;
    }
    return s;
}

/* -- values ----------------------------------------------------------------------------- */
#define READABLE (IN(S_INIT) | IN(S_STEP) | IN(S_TERMINATED))
#define WRITABLE (IN(S_INSTANTIATED) | IN(S_INIT) | IN(S_STEP))

#define GETTER(Name, name, ctype, type)                                                    \
    fmi2Status fmi2Get##Name(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,    \
                             ctype value[]) {                                              \
        INSTANCE(c, "fmi2Get" #Name);                                                      \
        if (require(in, "fmi2Get" #Name, READABLE) ||                                      \
            check_refs(in, "fmi2Get" #Name, vr, nvr, value, type))                         \
            return fmi2Error;                                                              \
        if (nvr == 0) return fmi2OK;                                                       \
        return answer(in, "fmi2Get" #Name, backend_get_##name(in, vr, nvr, value));        \
    }
GETTER(Real, real, fmi2Real, T_REAL)
GETTER(Integer, integer, fmi2Integer, T_INTEGER)
GETTER(Boolean, boolean, fmi2Boolean, T_BOOLEAN)
GETTER(String, string, fmi2String, T_STRING)

#define SETTER(Name, name, ctype, type, extra)                                             \
    fmi2Status fmi2Set##Name(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,    \
                             const ctype value[]) {                                        \
        INSTANCE(c, "fmi2Set" #Name);                                                      \
        if (require(in, "fmi2Set" #Name, WRITABLE) ||                                      \
            check_refs(in, "fmi2Set" #Name, vr, nvr, value, type) ||                       \
            check_settable(in, "fmi2Set" #Name, vr, nvr))                                  \
            return fmi2Error;                                                              \
        extra;                                                                             \
        if (nvr == 0) return fmi2OK;                                                       \
        return answer(in, "fmi2Set" #Name, backend_set_##name(in, vr, nvr, value));        \
    }
SETTER(Real, real, fmi2Real, T_REAL, )
SETTER(Integer, integer, fmi2Integer, T_INTEGER, )
SETTER(Boolean, boolean, fmi2Boolean, T_BOOLEAN,
       for (size_t i = 0; i < nvr; i++) if (value[i] != fmi2True && value[i] != fmi2False)
           return say(in, fmi2Error, "fmi2SetBoolean: value %d for '%s' is neither fmi2True "
                      "nor fmi2False", (int)value[i], VARIABLES[vr[i]].name))
SETTER(String, string, fmi2String, T_STRING,
       for (size_t i = 0; i < nvr; i++) if (!value[i] || !utf8((const unsigned char *)value[i]))
           return say(in, fmi2Error, "fmi2SetString: the value for '%s' is %s",
                      VARIABLES[vr[i]].name, value[i] ? "not valid UTF-8" : "NULL"))

/* -- stepping --------------------------------------------------------------------------- */
fmi2Status fmi2DoStep(fmi2Component c, fmi2Real currentCommunicationPoint,
                      fmi2Real communicationStepSize, fmi2Boolean noSetFMUStatePriorToCurrentPoint) {
    INSTANCE(c, "fmi2DoStep");
    if (require(in, "fmi2DoStep", IN(S_STEP))) return fmi2Error;
    if (!isfinite(currentCommunicationPoint))
        return say(in, fmi2Error, "fmi2DoStep: currentCommunicationPoint = %g is not finite",
                   currentCommunicationPoint);
    if (!(communicationStepSize > 0.0) || !isfinite(communicationStepSize))
        return say(in, fmi2Error, "fmi2DoStep: communicationStepSize = %g is not a positive "
                   "finite number", communicationStepSize);
    fmi2Status s = answer(in, "fmi2DoStep",
                          backend_do_step(in, currentCommunicationPoint, communicationStepSize,
                                          noSetFMUStatePriorToCurrentPoint));
    in->discarded = s == fmi2Discard;
    if (s <= fmi2Warning) in->time = currentCommunicationPoint + communicationStepSize;
    return s;
}

fmi2Status fmi2CancelStep(fmi2Component c) {
    INSTANCE(c, "fmi2CancelStep");
    return say(in, fmi2Error, "fmi2CancelStep: no step is pending (doStep never returns "
               "fmi2Pending)");
}

fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status *value) {
    INSTANCE(c, "fmi2GetStatus");
    (void)s;
    (void)value;
    return say(in, fmi2Discard, "fmi2GetStatus: no step is pending");
}

fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real *value) {
    INSTANCE(c, "fmi2GetRealStatus");
    if (!value) return say(in, fmi2Error, "fmi2GetRealStatus: value is NULL");
    if (s != fmi2LastSuccessfulTime)
        return say(in, fmi2Discard, "fmi2GetRealStatus: only fmi2LastSuccessfulTime is known");
    *value = in->time;
    return fmi2OK;
}

fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s, fmi2Integer *value) {
    INSTANCE(c, "fmi2GetIntegerStatus");
    (void)s;
    (void)value;
    return say(in, fmi2Discard, "fmi2GetIntegerStatus: no integer status is defined");
}

fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s, fmi2Boolean *value) {
    INSTANCE(c, "fmi2GetBooleanStatus");
    if (!value) return say(in, fmi2Error, "fmi2GetBooleanStatus: value is NULL");
    if (s != fmi2Terminated)
        return say(in, fmi2Discard, "fmi2GetBooleanStatus: only fmi2Terminated is known");
    /* after a discarded step the slave asks to end the run (a master that retries the
     * same inputs would retry forever); a later valid step is still taken */
    *value = in->discarded;
    return fmi2OK;
}

fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind s, fmi2String *value) {
    INSTANCE(c, "fmi2GetStringStatus");
    (void)s;
    (void)value;
    return say(in, fmi2Discard, "fmi2GetStringStatus: no string status is defined");
}

fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                       const fmi2Integer order[], const fmi2Real value[]) {
    INSTANCE(c, "fmi2SetRealInputDerivatives");
    (void)vr, (void)nvr, (void)order, (void)value;
    return say(in, fmi2Error, "fmi2SetRealInputDerivatives: not supported "
               "(canInterpolateInputs is false)");
}

fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[],
                                        size_t nvr, const fmi2Integer order[], fmi2Real value[]) {
    INSTANCE(c, "fmi2GetRealOutputDerivatives");
    (void)vr, (void)nvr, (void)order, (void)value;
    return say(in, fmi2Error, "fmi2GetRealOutputDerivatives: not supported "
               "(maxOutputDerivativeOrder is 0)");
}

fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference vUnknown[],
                                        size_t nUnknown, const fmi2ValueReference vKnown[],
                                        size_t nKnown, const fmi2Real dvKnown[],
                                        fmi2Real dvUnknown[]) {
    INSTANCE(c, "fmi2GetDirectionalDerivative");
    (void)vUnknown, (void)nUnknown, (void)vKnown, (void)nKnown, (void)dvKnown, (void)dvUnknown;
    return say(in, fmi2Error, "fmi2GetDirectionalDerivative: not supported "
               "(providesDirectionalDerivative is false)");
}

/* -- FMU state -------------------------------------------------------------------------- */
static SavedState *saved(const Instance *in, const char *call, fmi2FMUstate state) {
    SavedState *s = (SavedState *)state;
    if (!s) {
        say(in, fmi2Error, "%s: the FMU state is NULL", call);
        return NULL;
    }
    if (memcmp(s->magic, STATE_MAGIC, sizeof STATE_MAGIC) || s->guid != THIS_MODEL) {
        say(in, fmi2Error, "%s: the FMU state was not made by " MODEL_IDENTIFIER, call);
        return NULL;
    }
    return s;
}

fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *state) {
    INSTANCE(c, "fmi2GetFMUstate");
    if (!state) return say(in, fmi2Error, "fmi2GetFMUstate: the state pointer is NULL");
    SavedState *s = NULL;
    if (*state) { /* update a state returned before, in place */
        if (!(s = saved(in, "fmi2GetFMUstate", *state))) return fmi2Error;
    } else {
        s = (SavedState *)in->host.allocateMemory(1, sizeof *s);
        if (!s) return say(in, fmi2Error, "fmi2GetFMUstate: out of memory");
    }
    void *model = *state ? s->model : NULL;
    fmi2Status status = answer(in, "fmi2GetFMUstate", backend_get_state(in, &model));
    if (status > fmi2Warning || !model) {
        if (!*state) in->host.freeMemory(s);
        return status > fmi2Warning ? status : say(in, fmi2Error, "fmi2GetFMUstate: no state");
    }
    memcpy(s->magic, STATE_MAGIC, sizeof STATE_MAGIC);
    s->guid = THIS_MODEL;
    s->time = in->time;
    s->model = model;
    *state = s;
    return status;
}

fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate state) {
    INSTANCE(c, "fmi2SetFMUstate");
    if (require(in, "fmi2SetFMUstate", IN(S_INSTANTIATED) | IN(S_INIT) | IN(S_STEP) |
                                           IN(S_TERMINATED)))
        return fmi2Error;
    SavedState *s = saved(in, "fmi2SetFMUstate", state);
    if (!s) return fmi2Error;
    fmi2Status status = answer(in, "fmi2SetFMUstate", backend_set_state(in, s->model));
    if (status <= fmi2Warning) {
        in->time = s->time;
        in->discarded = fmi2False;
    }
    return status;
}

fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *state) {
    INSTANCE(c, "fmi2FreeFMUstate");
    if (!state) return say(in, fmi2Error, "fmi2FreeFMUstate: the state pointer is NULL");
    if (!*state) return fmi2OK;
    SavedState *s = saved(in, "fmi2FreeFMUstate", *state);
    if (!s) return fmi2Error;
    backend_free_state(in, s->model);
    memset(s->magic, 0, sizeof s->magic);
    in->host.freeMemory(s);
    *state = NULL;
    return fmi2OK;
}

/* Serialized states: the layout in fmi_common.h. */
fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate state, size_t *size) {
    INSTANCE(c, "fmi2SerializedFMUstateSize");
    if (!size) return say(in, fmi2Error, "fmi2SerializedFMUstateSize: size is NULL");
    SavedState *s = saved(in, "fmi2SerializedFMUstateSize", state);
    if (!s) return fmi2Error;
    size_t n = 0;
    fmi2Status status = answer(in, "fmi2SerializedFMUstateSize",
                               backend_state_size(in, s->model, &n));
    if (status <= fmi2Warning) *size = header_size() + n + 4;
    return status;
}


fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate state, fmi2Byte bytes[],
                                 size_t size) {
    INSTANCE(c, "fmi2SerializeFMUstate");
    SavedState *s = saved(in, "fmi2SerializeFMUstate", state);
    if (!s) return fmi2Error;
    if (!bytes) return say(in, fmi2Error, "fmi2SerializeFMUstate: bytes is NULL");
    size_t n = 0;
    fmi2Status status = answer(in, "fmi2SerializeFMUstate", backend_state_size(in, s->model, &n));
    if (status > fmi2Warning) return status;
    if (size != header_size() + n + 4)
        return say(in, fmi2Error, "fmi2SerializeFMUstate: size = %zu, but the state needs %zu "
                   "bytes (fmi2SerializedFMUstateSize)", size, header_size() + n + 4);
    unsigned char *p = (unsigned char *)bytes;
    uint32_t format = STATE_FORMAT, nid = (uint32_t)strlen(MODEL_IDENTIFIER),
             nguid = (uint32_t)strlen(MODEL_GUID);
    uint64_t npayload = n;
    p = put(p, STATE_MAGIC, 8);
    p = put(p, &format, 4);
    p = put(p, &nid, 4);
    p = put(p, MODEL_IDENTIFIER, nid);
    p = put(p, &nguid, 4);
    p = put(p, MODEL_GUID, nguid);
    p = put(p, &s->time, 8);
    p = put(p, &npayload, 8);
    status = answer(in, "fmi2SerializeFMUstate", backend_serialize(in, s->model, p, n));
    if (status > fmi2Warning) return status;
    p += n;
    uint32_t crc = crc32((const unsigned char *)bytes, (size_t)(p - (unsigned char *)bytes));
    put(p, &crc, 4);
    return status;
}

fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte serializedState[], size_t size,
                                   fmi2FMUstate *state) {
    INSTANCE(c, "fmi2DeSerializeFMUstate");
    const char *call = "fmi2DeSerializeFMUstate";
    if (!serializedState || !state)
        return say(in, fmi2Error, "%s: %s is NULL", call, !state ? "state" : "serializedState");
    const unsigned char *b = (const unsigned char *)serializedState;
    const size_t head = header_size();
    uint32_t format, nid, nguid, crc;
    uint64_t n;
    double time;
    if (size < head + 4 || memcmp(b, STATE_MAGIC, 8))
        return say(in, fmi2Error, "%s: these %zu bytes are not a serialized linkage_fmu state",
                   call, size);
    memcpy(&format, b + 8, 4);
    memcpy(&nid, b + 12, 4);
    if (format != STATE_FORMAT)
        return say(in, fmi2Error, "%s: state format %u, this FMU reads format %u", call,
                   (unsigned)format, STATE_FORMAT);
    if (nid != strlen(MODEL_IDENTIFIER) || memcmp(b + 16, MODEL_IDENTIFIER, nid))
        return say(in, fmi2Error, "%s: the state is not of model " MODEL_IDENTIFIER, call);
    memcpy(&nguid, b + 16 + nid, 4);
    if (nguid != strlen(MODEL_GUID) || memcmp(b + 20 + nid, MODEL_GUID, nguid))
        return say(in, fmi2Error, "%s: the state was made by another build of " MODEL_IDENTIFIER
                   " (GUID differs)", call);
    memcpy(&time, b + 20 + nid + nguid, 8);
    memcpy(&n, b + 28 + nid + nguid, 8);
    if (n != size - head - 4)
        return say(in, fmi2Error, "%s: the state says %llu payload bytes, %zu were given", call,
                   (unsigned long long)n, size - head - 4);
    memcpy(&crc, b + size - 4, 4);
    if (crc != crc32(b, size - 4))
        return say(in, fmi2Error, "%s: checksum mismatch: the serialized state is corrupted",
                   call);
    if (!isfinite(time))
        return say(in, fmi2Error, "%s: the state's time is not finite", call);
    SavedState *s = (SavedState *)in->host.allocateMemory(1, sizeof *s);
    if (!s) return say(in, fmi2Error, "%s: out of memory", call);
    void *model = NULL;
    fmi2Status status = answer(in, call, backend_deserialize(in, b + head, (size_t)n, &model));
    if (status > fmi2Warning || !model) {
        in->host.freeMemory(s);
        return status > fmi2Warning ? status : say(in, fmi2Error, "%s: no state", call);
    }
    memcpy(s->magic, STATE_MAGIC, sizeof STATE_MAGIC);
    s->guid = THIS_MODEL;
    s->time = time;
    s->model = model;
    *state = s;
    return status;
}
