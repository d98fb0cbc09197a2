/* FMI 3.0 co-simulation framework of linkage_fmu's native FMUs.
 *
 * The FMI 3.0 counterpart of fmi2.c: compiled with the same generated `config.h` (the
 * model's identifier, GUID and variable table) and the same backend, included below as
 * BACKEND, through backend_fmi3.h, which maps the FMI 2.0 names of the backend interface
 * to FMI 3.0's. It keeps fmi2.c's rules:
 *
 * - every argument is checked before any state changes: null pointers, unknown value
 *   references, wrong types, nValues that is not nValueReferences (every variable is a
 *   scalar), variables that may not be set in the current state (fixed parameters after
 *   initialisation, outputs, the independent variable), strings that are not UTF-8,
 *   booleans that are neither true nor false, step sizes and times that are not finite and
 *   positive; a bad call is fmi3Error with a log naming the call, the reference and the
 *   reason, and the instance stays usable;
 * - the co-simulation state machine of FMI 3.0 without event mode: Instantiated ->
 *   InitializationMode -> StepMode -> Terminated; an fmi3ExitInitializationMode that the
 *   backend rejects (an invalid parameter set) leaves the instance in initialisation
 *   mode, to be fixed;
 * - fmi3Fatal never reaches the host: a backend that reports it marks the instance
 *   failed, which answers fmi3Error from then on;
 * - a discarded step (inputs that cannot be solved) answers fmi3Discard with
 *   *terminateSimulation = true and *lastSuccessfulTime = the start of the step; a later
 *   valid step is still taken;
 * - serialized states carry a header (model identifier, GUID, format version, length,
 *   CRC-32): a foreign or corrupted state is rejected with fmi3Error;
 * - the instantiation token passed to fmi3InstantiateCoSimulation must match.
 *
 * FMI 3.0 requires one independent variable: `time`, value reference N_VARIABLES (right
 * after the variable table), answered here from the last successful communication point
 * and never passed to the backend. FMI 3.0 has no memory callbacks: the instance's
 * `host` allocates with calloc and frees with free, so the backend's calls
 * (in->host.allocateMemory, in->host.freeMemory) are the same as under fmi2.c.
 * Model exchange, scheduled execution, event mode, clocks, configuration mode,
 * derivatives and the variable types the model has no variables of are answered with
 * fmi3Error (or NULL) and a log: every FMI 3.0 function is exported.
 */
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi3Functions.h"

enum { T_REAL, T_INTEGER, T_BOOLEAN, T_STRING };
/* what a variable is, for the FMI 3 rules on setting it */
enum { K_INPUT, K_FIXED, K_TUNABLE, K_OUTPUT, K_OTHER, K_INDEPENDENT };

typedef struct {
    int type;
    int kind;
    const char *name;
    int role;  /* what the backend makes of it (backend_native.c), and its position there */
    int index;
} Variable;

#include "config.h"
#include "fmi_common.h"

/* the independent variable, after the variable table */
#define TIME_VR ((fmi3ValueReference)N_VARIABLES)
static const Variable TIME_VARIABLE = {T_REAL, K_INDEPENDENT, "time", 0, 0};


typedef enum { S_INSTANTIATED, S_INIT, S_STEP, S_TERMINATED, S_FAILED } Machine;
static const char *MACHINE_NAMES[] = {"Instantiated", "InitializationMode", "StepMode",
                                      "Terminated", "failed"};

/* What the backend uses of the host (fmi2.c: the importer's fmi2CallbackFunctions). */
typedef struct {
    void *(*allocateMemory)(size_t, size_t);
    void (*freeMemory)(void *);
    fmi3InstanceEnvironment environment;
    fmi3LogMessageCallback logMessage;
} Host;

typedef struct Instance {
    char *name;
    Host host;
    void *model; /* the backend's */
    Machine machine;
    fmi3Boolean logging;
    unsigned categories;   /* bit i: LOG_CATEGORIES[i] enabled; 0 = all */
    double time;           /* the last successful communication point */
    fmi3Boolean discarded; /* the last step was discarded */
} Instance;

typedef struct {
    char magic[8];
    const char *guid;
    double time;
    void *model;
} SavedState;


static int category_enabled(const Instance *in, fmi3Status status, const char *category) {
    if (status >= fmi3Error) return 1; /* errors are always reported */
    if (!in->logging) return 0;
    if (!in->categories) return 1;
    for (unsigned i = 0; i < N_CATEGORIES; i++)
        if ((in->categories >> i & 1u) &&
            (!strcmp(LOG_CATEGORIES[i], "logAll") ||
             (category && !strcmp(category, LOG_CATEGORIES[i]))))
            return 1;
    return 0;
}

/* FMI 3.0's message is plain text (no printf format, unlike FMI 2.0's): passed as is. */
static void emit(const Instance *in, fmi3Status status, const char *category,
                 const char *message) {
    if (!in->host.logMessage || !category_enabled(in, status, category)) return;
    in->host.logMessage(in->host.environment, status, category, message);
}

static const char *status_category(fmi3Status status) {
    return status >= fmi3Error ? "logStatusError"
           : status == fmi3Discard ? "logStatusDiscard"
                                   : "logStatusWarning";
}

/* Log a message (printf-style) with `status`, and return `status`. */
static fmi3Status say(const Instance *in, fmi3Status status, const char *fmt, ...) {
    char text[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    emit(in, status, status_category(status), text);
    return status;
}


/* The backend interface, as fmi2.c declares it, in FMI 2.0 names mapped to FMI 3.0's. */
#include "backend_fmi3.h"

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
    if (!in) return fmi3Error;                                                             \
    if (in->machine == S_FAILED)                                                           \
        return say(in, fmi3Error, call ": this instance failed earlier and can only be freed");

static fmi3Status require(const Instance *in, const char *call, unsigned allowed) {
    if (allowed >> in->machine & 1u) return fmi3OK;
    return say(in, fmi3Error, "%s is not allowed in state %s", call,
               MACHINE_NAMES[in->machine]);
}
#define IN(s) (1u << (s))

/* A backend's answer: fmi3Fatal fails the instance for good. */
static fmi3Status answer(Instance *in, const char *call, fmi3Status status) {
    if (status == fmi3Fatal) {
        in->machine = S_FAILED;
        return say(in, fmi3Error, "%s failed fatally; this instance can only be freed", call);
    }
    return status > fmi3Fatal ? fmi3Error : status;
}

static fmi3Status worst(fmi3Status a, fmi3Status b) { return a > b ? a : b; }

/* -- argument checks -------------------------------------------------------------------- */
static const char *TYPE_NAMES[] = {"Float64", "Int32", "Boolean", "String"};

static const Variable *variable(fmi3ValueReference vr) {
    if (vr == TIME_VR) return &TIME_VARIABLE;
    if (vr < N_VARIABLES && VARIABLES[vr].name) return &VARIABLES[vr];
    return NULL;
}

/* `type` is one of T_*, or -1 for a type this model has no variables of (`type_name`). */
static fmi3Status check_refs(const Instance *in, const char *call, const fmi3ValueReference vr[],
                             size_t nvr, const void *values, size_t nvalues, int type,
                             const char *type_name) {
    if (nvalues != nvr)
        return say(in, fmi3Error, "%s: nValues = %zu with %zu value references: every variable "
                   "of " MODEL_IDENTIFIER " is a scalar, nValues must equal nValueReferences",
                   call, nvalues, nvr);
    if (nvr == 0) return fmi3OK;
    if (!vr || !values)
        return say(in, fmi3Error, "%s: %s is NULL with nValueReferences = %zu", call,
                   !vr ? "the value reference array" : "the value array", nvr);
    for (size_t i = 0; i < nvr; i++) {
        const Variable *v = variable(vr[i]);
        if (!v)
            return say(in, fmi3Error, "%s: value reference %u (entry %zu) is not a variable of "
                       MODEL_IDENTIFIER, call, (unsigned)vr[i], i);
        if (v->type != type)
            return say(in, fmi3Error, "%s: value reference %u ('%s') is a %s, not a %s", call,
                       (unsigned)vr[i], v->name, TYPE_NAMES[v->type], type_name);
    }
    return fmi3OK;
}

static fmi3Status check_settable(const Instance *in, const char *call,
                                 const fmi3ValueReference vr[], size_t nvr) {
    for (size_t i = 0; i < nvr; i++) {
        const Variable *v = variable(vr[i]);
        if (v->kind == K_INPUT || v->kind == K_TUNABLE) continue;
        if (v->kind == K_FIXED && (in->machine == S_INSTANTIATED || in->machine == S_INIT))
            continue;
        return say(in, fmi3Error, "%s: '%s' (value reference %u) %s", call, v->name,
                   (unsigned)vr[i],
                   v->kind == K_FIXED ? "is a fixed parameter: it can only be set before "
                                        "fmi3ExitInitializationMode"
                   : v->kind == K_INDEPENDENT ? "is the independent variable: it cannot be set"
                                              : "is an output: it cannot be set");
    }
    return fmi3OK;
}

/* -- inquiry, instances, logging -------------------------------------------------------- */
const char *fmi3GetVersion(void) { return fmi3Version; }

static void refuse(const char *call, fmi3String name, fmi3InstanceEnvironment environment,
                   fmi3LogMessageCallback logMessage, const char *why) {
    Instance probe = {0};
    probe.name = (char *)(name ? name : "?");
    probe.host.environment = environment;
    probe.host.logMessage = logMessage;
    say(&probe, fmi3Error, "%s: %s", call, why);
}

fmi3Instance fmi3InstantiateCoSimulation(
    fmi3String instanceName, fmi3String instantiationToken, fmi3String resourcePath,
    fmi3Boolean visible, fmi3Boolean loggingOn, fmi3Boolean eventModeUsed,
    fmi3Boolean earlyReturnAllowed, const fmi3ValueReference requiredIntermediateVariables[],
    size_t nRequiredIntermediateVariables, fmi3InstanceEnvironment instanceEnvironment,
    fmi3LogMessageCallback logMessage, fmi3IntermediateUpdateCallback intermediateUpdate) {
    const char *call = "fmi3InstantiateCoSimulation";
    (void)earlyReturnAllowed; /* doStep never returns early */
    (void)intermediateUpdate; /* providesIntermediateUpdate is false: never called */
    char why[1024];
    why[0] = '\0';
    if (!instanceName || !*instanceName)
        snprintf(why, sizeof why, "the instance name is empty");
    else if (!instantiationToken || strcmp(instantiationToken, MODEL_GUID))
        snprintf(why, sizeof why, "instantiation token %s does not match this FMU's "
                 MODEL_GUID " (a modelDescription.xml of another FMU?)",
                 instantiationToken ? instantiationToken : "(null)");
    else if (eventModeUsed)
        snprintf(why, sizeof why, "eventModeUsed is true, but " MODEL_IDENTIFIER
                 " has no event mode (hasEventMode is false)");
    else if (nRequiredIntermediateVariables && !requiredIntermediateVariables)
        snprintf(why, sizeof why, "requiredIntermediateVariables is NULL with "
                 "nRequiredIntermediateVariables = %zu", nRequiredIntermediateVariables);
    else {
        for (size_t i = 0; i < nRequiredIntermediateVariables && !why[0]; i++)
            if (!variable(requiredIntermediateVariables[i]))
                snprintf(why, sizeof why, "required intermediate variable %u (entry %zu) is "
                         "not a variable of " MODEL_IDENTIFIER,
                         (unsigned)requiredIntermediateVariables[i], i);
        if (!why[0]) backend_ready(why, sizeof why);
    }
    if (why[0]) {
        refuse(call, instanceName, instanceEnvironment, logMessage, why);
        return NULL;
    }
    Instance *in = (Instance *)calloc(1, sizeof *in);
    char *name = (char *)calloc(strlen(instanceName) + 1, 1);
    if (!in || !name) {
        free(in);
        free(name);
        refuse(call, instanceName, instanceEnvironment, logMessage, "out of memory");
        return NULL;
    }
    strcpy(name, instanceName);
    in->name = name;
    in->host.allocateMemory = calloc;
    in->host.freeMemory = free;
    in->host.environment = instanceEnvironment;
    in->host.logMessage = logMessage;
    in->logging = loggingOn;
    in->machine = S_INSTANTIATED;
    /* resourcePath: an absolute path or NULL in FMI 3.0; the native backend reads none */
    in->model = backend_instantiate(in, instantiationToken, resourcePath, visible);
    if (!in->model) {
        free(name);
        free(in);
        return NULL;
    }
    return in;
}

fmi3Instance fmi3InstantiateModelExchange(fmi3String instanceName,
                                          fmi3String instantiationToken,
                                          fmi3String resourcePath, fmi3Boolean visible,
                                          fmi3Boolean loggingOn,
                                          fmi3InstanceEnvironment instanceEnvironment,
                                          fmi3LogMessageCallback logMessage) {
    (void)instantiationToken, (void)resourcePath, (void)visible, (void)loggingOn;
    refuse("fmi3InstantiateModelExchange", instanceName, instanceEnvironment, logMessage,
           MODEL_IDENTIFIER " supports co-simulation only");
    return NULL;
}

fmi3Instance fmi3InstantiateScheduledExecution(
    fmi3String instanceName, fmi3String instantiationToken, fmi3String resourcePath,
    fmi3Boolean visible, fmi3Boolean loggingOn, fmi3InstanceEnvironment instanceEnvironment,
    fmi3LogMessageCallback logMessage, fmi3ClockUpdateCallback clockUpdate,
    fmi3LockPreemptionCallback lockPreemption, fmi3UnlockPreemptionCallback unlockPreemption) {
    (void)instantiationToken, (void)resourcePath, (void)visible, (void)loggingOn;
    (void)clockUpdate, (void)lockPreemption, (void)unlockPreemption;
    refuse("fmi3InstantiateScheduledExecution", instanceName, instanceEnvironment, logMessage,
           MODEL_IDENTIFIER " supports co-simulation only");
    return NULL;
}

void fmi3FreeInstance(fmi3Instance instance) {
    Instance *in = (Instance *)instance;
    if (!in) return;
    backend_free(in);
    free(in->name);
    free(in);
}

fmi3Status fmi3SetDebugLogging(fmi3Instance instance, fmi3Boolean loggingOn, size_t nCategories,
                               const fmi3String categories[]) {
    INSTANCE(instance, "fmi3SetDebugLogging");
    if (nCategories && !categories)
        return say(in, fmi3Error, "fmi3SetDebugLogging: categories is NULL with nCategories = "
                   "%zu", nCategories);
    unsigned mask = 0;
    for (size_t i = 0; i < nCategories; i++) {
        unsigned k = 0;
        while (k < N_CATEGORIES && !(categories[i] && !strcmp(categories[i], LOG_CATEGORIES[k])))
            k++;
        if (k == N_CATEGORIES)
            return say(in, fmi3Error, "fmi3SetDebugLogging: unknown log category '%s'; the "
                       "categories are logStatusWarning, logStatusDiscard, logStatusError, "
                       "logStatusFatal, logAll", categories[i] ? categories[i] : "(null)");
        mask |= 1u << k;
    }
    in->logging = loggingOn;
    in->categories = mask;
    return fmi3OK;
}

/* -- life cycle ------------------------------------------------------------------------- */
fmi3Status fmi3EnterInitializationMode(fmi3Instance instance, fmi3Boolean toleranceDefined,
                                       fmi3Float64 tolerance, fmi3Float64 startTime,
                                       fmi3Boolean stopTimeDefined, fmi3Float64 stopTime) {
    const char *call = "fmi3EnterInitializationMode";
    INSTANCE(instance, "fmi3EnterInitializationMode");
    if (require(in, call, IN(S_INSTANTIATED))) return fmi3Error;
    if (!isfinite(startTime))
        return say(in, fmi3Error, "%s: startTime = %g is not finite", call, startTime);
    if (stopTimeDefined && !(stopTime >= startTime))
        return say(in, fmi3Error, "%s: stopTime = %g is not >= startTime = %g", call, stopTime,
                   startTime);
    if (toleranceDefined && !(tolerance > 0.0 && isfinite(tolerance)))
        return say(in, fmi3Error, "%s: tolerance = %g is not a positive number", call,
                   tolerance);
    fmi3Status s = answer(in, call, backend_setup_experiment(in, toleranceDefined, tolerance,
                                                             startTime, stopTimeDefined,
                                                             stopTime));
    if (s > fmi3Warning) return s;
    s = worst(s, answer(in, call, backend_enter_initialization(in)));
    if (s <= fmi3Warning) {
        in->time = startTime;
        in->machine = S_INIT;
    }
    return s;
}

fmi3Status fmi3ExitInitializationMode(fmi3Instance instance) {
    INSTANCE(instance, "fmi3ExitInitializationMode");
    if (require(in, "fmi3ExitInitializationMode", IN(S_INIT))) return fmi3Error;
    fmi3Status s = answer(in, "fmi3ExitInitializationMode", backend_exit_initialization(in));
    /* an invalid parameter set leaves the instance in initialisation mode, to be fixed;
     * without event mode the instance goes straight to step mode */
    if (s <= fmi3Warning) in->machine = S_STEP;
    return s;
}

fmi3Status fmi3Terminate(fmi3Instance instance) {
    INSTANCE(instance, "fmi3Terminate");
    if (require(in, "fmi3Terminate", IN(S_STEP))) return fmi3Error;
    fmi3Status s = answer(in, "fmi3Terminate", backend_terminate(in));
    if (s <= fmi3Warning) in->machine = S_TERMINATED;
    return s;
}

fmi3Status fmi3Reset(fmi3Instance instance) {
    INSTANCE(instance, "fmi3Reset");
    fmi3Status s = answer(in, "fmi3Reset", backend_reset(in));
    if (s <= fmi3Warning) {
        in->machine = S_INSTANTIATED;
        in->time = 0.0;
        in->discarded = fmi3False;
    }
    return s;
}

/* -- values ----------------------------------------------------------------------------- */
#define READABLE (IN(S_INIT) | IN(S_STEP) | IN(S_TERMINATED))
#define WRITABLE (IN(S_INSTANTIATED) | IN(S_INIT) | IN(S_STEP))

/* Float64: the independent variable is the framework's; runs of the others go to the
 * backend. */
fmi3Status fmi3GetFloat64(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                          size_t nValueReferences, fmi3Float64 values[], size_t nValues) {
    const char *call = "fmi3GetFloat64";
    INSTANCE(instance, "fmi3GetFloat64");
    const fmi3ValueReference *vr = valueReferences;
    const size_t nvr = nValueReferences;
    if (require(in, call, READABLE) ||
        check_refs(in, call, vr, nvr, values, nValues, T_REAL, "Float64"))
        return fmi3Error;
    fmi3Status status = fmi3OK;
    for (size_t i = 0; i < nvr && status <= fmi3Discard;) {
        if (vr[i] == TIME_VR) {
            values[i++] = in->time;
            continue;
        }
        size_t j = i;
        while (j < nvr && vr[j] != TIME_VR) j++;
        status = worst(status, answer(in, call, backend_get_real(in, vr + i, j - i, values + i)));
        i = j;
    }
    return status;
}

#define GETTER(Name, name, ctype, type)                                                    \
    fmi3Status fmi3Get##Name(fmi3Instance instance, const fmi3ValueReference valueReferences[], \
                             size_t nValueReferences, ctype values[], size_t nValues) {    \
        INSTANCE(instance, "fmi3Get" #Name);                                               \
        if (require(in, "fmi3Get" #Name, READABLE) ||                                      \
            check_refs(in, "fmi3Get" #Name, valueReferences, nValueReferences, values,      \
                       nValues, type, #Name))                                              \
            return fmi3Error;                                                              \
        if (nValueReferences == 0) return fmi3OK;                                          \
        return answer(in, "fmi3Get" #Name,                                                 \
                      backend_get_##name(in, valueReferences, nValueReferences, values));  \
    }
GETTER(Int32, integer, fmi3Int32, T_INTEGER)
GETTER(Boolean, boolean, fmi3Boolean, T_BOOLEAN)
GETTER(String, string, fmi3String, T_STRING)

#define SETTER(Name, name, ctype, type, extra)                                             \
    fmi3Status fmi3Set##Name(fmi3Instance instance, const fmi3ValueReference valueReferences[], \
                             size_t nValueReferences, const ctype values[], size_t nValues) { \
        const fmi3ValueReference *vr = valueReferences;                                    \
        const size_t nvr = nValueReferences;                                               \
        INSTANCE(instance, "fmi3Set" #Name);                                               \
        if (require(in, "fmi3Set" #Name, WRITABLE) ||                                      \
            check_refs(in, "fmi3Set" #Name, vr, nvr, values, nValues, type, #Name) ||      \
            check_settable(in, "fmi3Set" #Name, vr, nvr))                                  \
            return fmi3Error;                                                              \
        extra;                                                                             \
        if (nvr == 0) return fmi3OK;                                                       \
        return answer(in, "fmi3Set" #Name, backend_set_##name(in, vr, nvr, values));       \
    }
SETTER(Float64, real, fmi3Float64, T_REAL, )
SETTER(Int32, integer, fmi3Int32, T_INTEGER, )
/* a C bool holds 0 or 1; a host writing another byte (ctypes can) is caught here */
SETTER(Boolean, boolean, fmi3Boolean, T_BOOLEAN,
       for (size_t i = 0; i < nvr; i++) if (((const unsigned char *)values)[i] > 1)
           return say(in, fmi3Error, "fmi3SetBoolean: value %d for '%s' is neither fmi3True "
                      "nor fmi3False", (int)((const unsigned char *)values)[i],
                      VARIABLES[vr[i]].name))
SETTER(String, string, fmi3String, T_STRING,
       for (size_t i = 0; i < nvr; i++) if (!values[i] || !utf8((const unsigned char *)values[i]))
           return say(in, fmi3Error, "fmi3SetString: the value for '%s' is %s",
                      VARIABLES[vr[i]].name, values[i] ? "not valid UTF-8" : "NULL"))

/* The types this model has no variables of: a call with references is a wrong type (or an
 * unknown reference), named as such; an empty call is fmi3OK in a state that allows it. */
#define NO_VARIABLES(Name, ctype, allowed)                                                  \
    fmi3Status fmi3##Name(fmi3Instance instance, const fmi3ValueReference valueReferences[], \
                          size_t nValueReferences, ctype values[], size_t nValues) {       \
        INSTANCE(instance, "fmi3" #Name);                                                  \
        if (require(in, "fmi3" #Name, allowed)) return fmi3Error;                          \
        return check_refs(in, "fmi3" #Name, valueReferences, nValueReferences, values,      \
                          nValues, -1, #Name + 3);                                         \
    }
NO_VARIABLES(GetFloat32, fmi3Float32, READABLE)
NO_VARIABLES(GetInt8, fmi3Int8, READABLE)
NO_VARIABLES(GetUInt8, fmi3UInt8, READABLE)
NO_VARIABLES(GetInt16, fmi3Int16, READABLE)
NO_VARIABLES(GetUInt16, fmi3UInt16, READABLE)
NO_VARIABLES(GetUInt32, fmi3UInt32, READABLE)
NO_VARIABLES(GetInt64, fmi3Int64, READABLE)
NO_VARIABLES(GetUInt64, fmi3UInt64, READABLE)
NO_VARIABLES(SetFloat32, const fmi3Float32, WRITABLE)
NO_VARIABLES(SetInt8, const fmi3Int8, WRITABLE)
NO_VARIABLES(SetUInt8, const fmi3UInt8, WRITABLE)
NO_VARIABLES(SetInt16, const fmi3Int16, WRITABLE)
NO_VARIABLES(SetUInt16, const fmi3UInt16, WRITABLE)
NO_VARIABLES(SetUInt32, const fmi3UInt32, WRITABLE)
NO_VARIABLES(SetInt64, const fmi3Int64, WRITABLE)
NO_VARIABLES(SetUInt64, const fmi3UInt64, WRITABLE)

fmi3Status fmi3GetBinary(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                         size_t nValueReferences, size_t valueSizes[], fmi3Binary values[],
                         size_t nValues) {
    INSTANCE(instance, "fmi3GetBinary");
    if (require(in, "fmi3GetBinary", READABLE)) return fmi3Error;
    if (nValueReferences && !valueSizes)
        return say(in, fmi3Error, "fmi3GetBinary: valueSizes is NULL");
    return check_refs(in, "fmi3GetBinary", valueReferences, nValueReferences, values, nValues,
                      -1, "Binary");
}

fmi3Status fmi3SetBinary(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                         size_t nValueReferences, const size_t valueSizes[],
                         const fmi3Binary values[], size_t nValues) {
    INSTANCE(instance, "fmi3SetBinary");
    if (require(in, "fmi3SetBinary", WRITABLE)) return fmi3Error;
    if (nValueReferences && !valueSizes)
        return say(in, fmi3Error, "fmi3SetBinary: valueSizes is NULL");
    return check_refs(in, "fmi3SetBinary", valueReferences, nValueReferences, values, nValues,
                      -1, "Binary");
}

fmi3Status fmi3GetClock(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                        size_t nValueReferences, fmi3Clock values[]) {
    INSTANCE(instance, "fmi3GetClock");
    return check_refs(in, "fmi3GetClock", valueReferences, nValueReferences, values,
                      nValueReferences, -1, "Clock");
}

fmi3Status fmi3SetClock(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                        size_t nValueReferences, const fmi3Clock values[]) {
    INSTANCE(instance, "fmi3SetClock");
    return check_refs(in, "fmi3SetClock", valueReferences, nValueReferences, values,
                      nValueReferences, -1, "Clock");
}

/* -- stepping --------------------------------------------------------------------------- */
fmi3Status fmi3DoStep(fmi3Instance instance, fmi3Float64 currentCommunicationPoint,
                      fmi3Float64 communicationStepSize,
                      fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                      fmi3Boolean *eventHandlingNeeded, fmi3Boolean *terminateSimulation,
                      fmi3Boolean *earlyReturn, fmi3Float64 *lastSuccessfulTime) {
    const char *call = "fmi3DoStep";
    const double t = currentCommunicationPoint, h = communicationStepSize;
    INSTANCE(instance, "fmi3DoStep");
    if (require(in, call, IN(S_STEP))) return fmi3Error;
    if (!eventHandlingNeeded || !terminateSimulation || !earlyReturn || !lastSuccessfulTime)
        return say(in, fmi3Error, "%s: %s is NULL", call,
                   !eventHandlingNeeded ? "eventHandlingNeeded"
                   : !terminateSimulation ? "terminateSimulation"
                   : !earlyReturn ? "earlyReturn" : "lastSuccessfulTime");
    *eventHandlingNeeded = fmi3False;
    *terminateSimulation = fmi3False;
    *earlyReturn = fmi3False;
    *lastSuccessfulTime = in->time;
    if (!isfinite(t))
        return say(in, fmi3Error, "%s: currentCommunicationPoint = %g is not finite", call, t);
    if (!(h > 0.0) || !isfinite(h))
        return say(in, fmi3Error, "%s: communicationStepSize = %g is not a positive finite "
                   "number", call, h);
    fmi3Status s = answer(in, call, backend_do_step(in, t, h, noSetFMUStatePriorToCurrentPoint));
    in->discarded = s == fmi3Discard;
    if (s <= fmi3Warning) {
        in->time = t + h;
        *lastSuccessfulTime = in->time;
    } else if (s == fmi3Discard) {
        /* nothing of the step was done; the slave asks to end the run (a master that
         * retries the same inputs would retry forever); a later valid step is still taken */
        *lastSuccessfulTime = t;
        *terminateSimulation = fmi3True;
    }
    return s;
}

/* -- FMU state -------------------------------------------------------------------------- */
static SavedState *saved(const Instance *in, const char *call, fmi3FMUState state) {
    SavedState *s = (SavedState *)state;
    if (!s) {
        say(in, fmi3Error, "%s: the FMU state is NULL", call);
        return NULL;
    }
    if (memcmp(s->magic, STATE_MAGIC, sizeof STATE_MAGIC) || s->guid != THIS_MODEL) {
        say(in, fmi3Error, "%s: the FMU state was not made by " MODEL_IDENTIFIER, call);
        return NULL;
    }
    return s;
}

fmi3Status fmi3GetFMUState(fmi3Instance instance, fmi3FMUState *state) {
    INSTANCE(instance, "fmi3GetFMUState");
    if (!state) return say(in, fmi3Error, "fmi3GetFMUState: the state pointer is NULL");
    SavedState *s = NULL;
    if (*state) { /* update a state returned before, in place */
        if (!(s = saved(in, "fmi3GetFMUState", *state))) return fmi3Error;
    } else {
        s = (SavedState *)calloc(1, sizeof *s);
        if (!s) return say(in, fmi3Error, "fmi3GetFMUState: out of memory");
    }
    void *model = *state ? s->model : NULL;
    fmi3Status status = answer(in, "fmi3GetFMUState", backend_get_state(in, &model));
    if (status > fmi3Warning || !model) {
        if (!*state) free(s);
        return status > fmi3Warning ? status : say(in, fmi3Error, "fmi3GetFMUState: no state");
    }
    memcpy(s->magic, STATE_MAGIC, sizeof STATE_MAGIC);
    s->guid = THIS_MODEL;
    s->time = in->time;
    s->model = model;
    *state = s;
    return status;
}

fmi3Status fmi3SetFMUState(fmi3Instance instance, fmi3FMUState state) {
    INSTANCE(instance, "fmi3SetFMUState");
    if (require(in, "fmi3SetFMUState", IN(S_INSTANTIATED) | IN(S_INIT) | IN(S_STEP) |
                                           IN(S_TERMINATED)))
        return fmi3Error;
    SavedState *s = saved(in, "fmi3SetFMUState", state);
    if (!s) return fmi3Error;
    fmi3Status status = answer(in, "fmi3SetFMUState", backend_set_state(in, s->model));
    if (status <= fmi3Warning) {
        in->time = s->time;
        in->discarded = fmi3False;
    }
    return status;
}

fmi3Status fmi3FreeFMUState(fmi3Instance instance, fmi3FMUState *state) {
    INSTANCE(instance, "fmi3FreeFMUState");
    if (!state) return say(in, fmi3Error, "fmi3FreeFMUState: the state pointer is NULL");
    if (!*state) return fmi3OK;
    SavedState *s = saved(in, "fmi3FreeFMUState", *state);
    if (!s) return fmi3Error;
    backend_free_state(in, s->model);
    memset(s->magic, 0, sizeof s->magic);
    free(s);
    *state = NULL;
    return fmi3OK;
}

/* Serialized states: the layout in fmi_common.h. */
fmi3Status fmi3SerializedFMUStateSize(fmi3Instance instance, fmi3FMUState state, size_t *size) {
    INSTANCE(instance, "fmi3SerializedFMUStateSize");
    if (!size) return say(in, fmi3Error, "fmi3SerializedFMUStateSize: size is NULL");
    SavedState *s = saved(in, "fmi3SerializedFMUStateSize", state);
    if (!s) return fmi3Error;
    size_t n = 0;
    fmi3Status status = answer(in, "fmi3SerializedFMUStateSize",
                               backend_state_size(in, s->model, &n));
    if (status <= fmi3Warning) *size = header_size() + n + 4;
    return status;
}


fmi3Status fmi3SerializeFMUState(fmi3Instance instance, fmi3FMUState state,
                                 fmi3Byte serializedState[], size_t size) {
    INSTANCE(instance, "fmi3SerializeFMUState");
    SavedState *s = saved(in, "fmi3SerializeFMUState", state);
    if (!s) return fmi3Error;
    if (!serializedState)
        return say(in, fmi3Error, "fmi3SerializeFMUState: serializedState is NULL");
    size_t n = 0;
    fmi3Status status = answer(in, "fmi3SerializeFMUState", backend_state_size(in, s->model, &n));
    if (status > fmi3Warning) return status;
    if (size != header_size() + n + 4)
        return say(in, fmi3Error, "fmi3SerializeFMUState: size = %zu, but the state needs %zu "
                   "bytes (fmi3SerializedFMUStateSize)", size, header_size() + n + 4);
    unsigned char *p = (unsigned char *)serializedState;
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
    status = answer(in, "fmi3SerializeFMUState", backend_serialize(in, s->model, p, n));
    if (status > fmi3Warning) return status;
    p += n;
    uint32_t crc = crc32(serializedState, (size_t)(p - serializedState));
    put(p, &crc, 4);
    return status;
}

fmi3Status fmi3DeserializeFMUState(fmi3Instance instance, const fmi3Byte serializedState[],
                                   size_t size, fmi3FMUState *state) {
    INSTANCE(instance, "fmi3DeserializeFMUState");
    const char *call = "fmi3DeserializeFMUState";
    if (!serializedState || !state)
        return say(in, fmi3Error, "%s: %s is NULL", call, !state ? "state" : "serializedState");
    const unsigned char *b = serializedState;
    const size_t head = header_size();
    uint32_t format, nid, nguid, crc;
    uint64_t n;
    double time;
    if (size < head + 4 || memcmp(b, STATE_MAGIC, 8))
        return say(in, fmi3Error, "%s: these %zu bytes are not a serialized linkage_fmu state",
                   call, size);
    memcpy(&format, b + 8, 4);
    memcpy(&nid, b + 12, 4);
    if (format != STATE_FORMAT)
        return say(in, fmi3Error, "%s: state format %u, this FMU reads format %u", call,
                   (unsigned)format, STATE_FORMAT);
    if (nid != strlen(MODEL_IDENTIFIER) || memcmp(b + 16, MODEL_IDENTIFIER, nid))
        return say(in, fmi3Error, "%s: the state is not of model " MODEL_IDENTIFIER, call);
    memcpy(&nguid, b + 16 + nid, 4);
    if (nguid != strlen(MODEL_GUID) || memcmp(b + 20 + nid, MODEL_GUID, nguid))
        return say(in, fmi3Error, "%s: the state was made by another build of " MODEL_IDENTIFIER
                   " (instantiation token differs)", call);
    memcpy(&time, b + 20 + nid + nguid, 8);
    memcpy(&n, b + 28 + nid + nguid, 8);
    if (n != size - head - 4)
        return say(in, fmi3Error, "%s: the state says %llu payload bytes, %zu were given", call,
                   (unsigned long long)n, size - head - 4);
    memcpy(&crc, b + size - 4, 4);
    if (crc != crc32(b, size - 4))
        return say(in, fmi3Error, "%s: checksum mismatch: the serialized state is corrupted",
                   call);
    if (!isfinite(time))
        return say(in, fmi3Error, "%s: the state's time is not finite", call);
    SavedState *s = (SavedState *)calloc(1, sizeof *s);
    if (!s) return say(in, fmi3Error, "%s: out of memory", call);
    void *model = NULL;
    fmi3Status status = answer(in, call, backend_deserialize(in, b + head, (size_t)n, &model));
    if (status > fmi3Warning || !model) {
        free(s);
        return status > fmi3Warning ? status : say(in, fmi3Error, "%s: no state", call);
    }
    memcpy(s->magic, STATE_MAGIC, sizeof STATE_MAGIC);
    s->guid = THIS_MODEL;
    s->time = time;
    s->model = model;
    *state = s;
    return status;
}

/* -- not supported: every other FMI 3.0 function answers fmi3Error with a log ------------- */
#define UNSUPPORTED(name, why)                                                             \
    INSTANCE(instance, #name);                                                             \
    return say(in, fmi3Error, #name ": not supported (" why ")")

fmi3Status fmi3EnterEventMode(fmi3Instance instance) {
    UNSUPPORTED(fmi3EnterEventMode, "hasEventMode is false");
}

fmi3Status fmi3EnterStepMode(fmi3Instance instance) {
    UNSUPPORTED(fmi3EnterStepMode, "eventModeUsed is false: fmi3ExitInitializationMode "
                "enters step mode");
}

fmi3Status fmi3GetNumberOfVariableDependencies(fmi3Instance instance,
                                               fmi3ValueReference valueReference,
                                               size_t *nDependencies) {
    (void)valueReference, (void)nDependencies;
    UNSUPPORTED(fmi3GetNumberOfVariableDependencies, "providesPerElementDependencies is "
                "false; the dependencies are in the modelDescription's ModelStructure");
}

fmi3Status fmi3GetVariableDependencies(fmi3Instance instance, fmi3ValueReference dependent,
                                       size_t elementIndicesOfDependent[],
                                       fmi3ValueReference independents[],
                                       size_t elementIndicesOfIndependents[],
                                       fmi3DependencyKind dependencyKinds[],
                                       size_t nDependencies) {
    (void)dependent, (void)elementIndicesOfDependent, (void)independents;
    (void)elementIndicesOfIndependents, (void)dependencyKinds, (void)nDependencies;
    UNSUPPORTED(fmi3GetVariableDependencies, "providesPerElementDependencies is false; the "
                "dependencies are in the modelDescription's ModelStructure");
}

fmi3Status fmi3GetDirectionalDerivative(fmi3Instance instance,
                                        const fmi3ValueReference unknowns[], size_t nUnknowns,
                                        const fmi3ValueReference knowns[], size_t nKnowns,
                                        const fmi3Float64 seed[], size_t nSeed,
                                        fmi3Float64 sensitivity[], size_t nSensitivity) {
    (void)unknowns, (void)nUnknowns, (void)knowns, (void)nKnowns, (void)seed, (void)nSeed;
    (void)sensitivity, (void)nSensitivity;
    UNSUPPORTED(fmi3GetDirectionalDerivative, "providesDirectionalDerivatives is false");
}

fmi3Status fmi3GetAdjointDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[],
                                    size_t nUnknowns, const fmi3ValueReference knowns[],
                                    size_t nKnowns, const fmi3Float64 seed[], size_t nSeed,
                                    fmi3Float64 sensitivity[], size_t nSensitivity) {
    (void)unknowns, (void)nUnknowns, (void)knowns, (void)nKnowns, (void)seed, (void)nSeed;
    (void)sensitivity, (void)nSensitivity;
    UNSUPPORTED(fmi3GetAdjointDerivative, "providesAdjointDerivatives is false");
}

fmi3Status fmi3EnterConfigurationMode(fmi3Instance instance) {
    UNSUPPORTED(fmi3EnterConfigurationMode, MODEL_IDENTIFIER " has no structural parameters");
}

fmi3Status fmi3ExitConfigurationMode(fmi3Instance instance) {
    UNSUPPORTED(fmi3ExitConfigurationMode, MODEL_IDENTIFIER " has no structural parameters");
}

#define NO_CLOCKS "no clocks"
fmi3Status fmi3GetIntervalDecimal(fmi3Instance instance,
                                  const fmi3ValueReference valueReferences[],
                                  size_t nValueReferences, fmi3Float64 intervals[],
                                  fmi3IntervalQualifier qualifiers[]) {
    (void)valueReferences, (void)nValueReferences, (void)intervals, (void)qualifiers;
    UNSUPPORTED(fmi3GetIntervalDecimal, NO_CLOCKS);
}

fmi3Status fmi3GetIntervalFraction(fmi3Instance instance,
                                   const fmi3ValueReference valueReferences[],
                                   size_t nValueReferences, fmi3UInt64 counters[],
                                   fmi3UInt64 resolutions[], fmi3IntervalQualifier qualifiers[]) {
    (void)valueReferences, (void)nValueReferences, (void)counters, (void)resolutions;
    (void)qualifiers;
    UNSUPPORTED(fmi3GetIntervalFraction, NO_CLOCKS);
}

fmi3Status fmi3GetShiftDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                               size_t nValueReferences, fmi3Float64 shifts[]) {
    (void)valueReferences, (void)nValueReferences, (void)shifts;
    UNSUPPORTED(fmi3GetShiftDecimal, NO_CLOCKS);
}

fmi3Status fmi3GetShiftFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                size_t nValueReferences, fmi3UInt64 counters[],
                                fmi3UInt64 resolutions[]) {
    (void)valueReferences, (void)nValueReferences, (void)counters, (void)resolutions;
    UNSUPPORTED(fmi3GetShiftFraction, NO_CLOCKS);
}

fmi3Status fmi3SetIntervalDecimal(fmi3Instance instance,
                                  const fmi3ValueReference valueReferences[],
                                  size_t nValueReferences, const fmi3Float64 intervals[]) {
    (void)valueReferences, (void)nValueReferences, (void)intervals;
    UNSUPPORTED(fmi3SetIntervalDecimal, NO_CLOCKS);
}

fmi3Status fmi3SetIntervalFraction(fmi3Instance instance,
                                   const fmi3ValueReference valueReferences[],
                                   size_t nValueReferences, const fmi3UInt64 counters[],
                                   const fmi3UInt64 resolutions[]) {
    (void)valueReferences, (void)nValueReferences, (void)counters, (void)resolutions;
    UNSUPPORTED(fmi3SetIntervalFraction, NO_CLOCKS);
}

fmi3Status fmi3SetShiftDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                               size_t nValueReferences, const fmi3Float64 shifts[]) {
    (void)valueReferences, (void)nValueReferences, (void)shifts;
    UNSUPPORTED(fmi3SetShiftDecimal, NO_CLOCKS);
}

fmi3Status fmi3SetShiftFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                size_t nValueReferences, const fmi3UInt64 counters[],
                                const fmi3UInt64 resolutions[]) {
    (void)valueReferences, (void)nValueReferences, (void)counters, (void)resolutions;
    UNSUPPORTED(fmi3SetShiftFraction, NO_CLOCKS);
}

fmi3Status fmi3EvaluateDiscreteStates(fmi3Instance instance) {
    UNSUPPORTED(fmi3EvaluateDiscreteStates, "providesEvaluateDiscreteStates is false");
}

fmi3Status fmi3UpdateDiscreteStates(fmi3Instance instance, fmi3Boolean *discreteStatesNeedUpdate,
                                    fmi3Boolean *terminateSimulation,
                                    fmi3Boolean *nominalsOfContinuousStatesChanged,
                                    fmi3Boolean *valuesOfContinuousStatesChanged,
                                    fmi3Boolean *nextEventTimeDefined,
                                    fmi3Float64 *nextEventTime) {
    (void)discreteStatesNeedUpdate, (void)terminateSimulation;
    (void)nominalsOfContinuousStatesChanged, (void)valuesOfContinuousStatesChanged;
    (void)nextEventTimeDefined, (void)nextEventTime;
    UNSUPPORTED(fmi3UpdateDiscreteStates, "hasEventMode is false");
}

#define CS_ONLY "model exchange: " MODEL_IDENTIFIER " supports co-simulation only"
fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance instance) {
    UNSUPPORTED(fmi3EnterContinuousTimeMode, CS_ONLY);
}

fmi3Status fmi3CompletedIntegratorStep(fmi3Instance instance,
                                       fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi3Boolean *enterEventMode,
                                       fmi3Boolean *terminateSimulation) {
    (void)noSetFMUStatePriorToCurrentPoint, (void)enterEventMode, (void)terminateSimulation;
    UNSUPPORTED(fmi3CompletedIntegratorStep, CS_ONLY);
}

fmi3Status fmi3SetTime(fmi3Instance instance, fmi3Float64 time) {
    (void)time;
    UNSUPPORTED(fmi3SetTime, CS_ONLY);
}

fmi3Status fmi3SetContinuousStates(fmi3Instance instance, const fmi3Float64 continuousStates[],
                                   size_t nContinuousStates) {
    (void)continuousStates, (void)nContinuousStates;
    UNSUPPORTED(fmi3SetContinuousStates, CS_ONLY);
}

fmi3Status fmi3GetContinuousStateDerivatives(fmi3Instance instance, fmi3Float64 derivatives[],
                                             size_t nContinuousStates) {
    (void)derivatives, (void)nContinuousStates;
    UNSUPPORTED(fmi3GetContinuousStateDerivatives, CS_ONLY);
}

fmi3Status fmi3GetEventIndicators(fmi3Instance instance, fmi3Float64 eventIndicators[],
                                  size_t nEventIndicators) {
    (void)eventIndicators, (void)nEventIndicators;
    UNSUPPORTED(fmi3GetEventIndicators, CS_ONLY);
}

fmi3Status fmi3GetContinuousStates(fmi3Instance instance, fmi3Float64 continuousStates[],
                                   size_t nContinuousStates) {
    (void)continuousStates, (void)nContinuousStates;
    UNSUPPORTED(fmi3GetContinuousStates, CS_ONLY);
}

fmi3Status fmi3GetNominalsOfContinuousStates(fmi3Instance instance, fmi3Float64 nominals[],
                                             size_t nContinuousStates) {
    (void)nominals, (void)nContinuousStates;
    UNSUPPORTED(fmi3GetNominalsOfContinuousStates, CS_ONLY);
}

fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance instance, size_t *nEventIndicators) {
    (void)nEventIndicators;
    UNSUPPORTED(fmi3GetNumberOfEventIndicators, CS_ONLY);
}

fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance instance, size_t *nContinuousStates) {
    (void)nContinuousStates;
    UNSUPPORTED(fmi3GetNumberOfContinuousStates, CS_ONLY);
}

fmi3Status fmi3GetOutputDerivatives(fmi3Instance instance,
                                    const fmi3ValueReference valueReferences[],
                                    size_t nValueReferences, const fmi3Int32 orders[],
                                    fmi3Float64 values[], size_t nValues) {
    (void)valueReferences, (void)nValueReferences, (void)orders, (void)values, (void)nValues;
    UNSUPPORTED(fmi3GetOutputDerivatives, "maxOutputDerivativeOrder is 0");
}

fmi3Status fmi3ActivateModelPartition(fmi3Instance instance, fmi3ValueReference clockReference,
                                      fmi3Float64 activationTime) {
    (void)clockReference, (void)activationTime;
    UNSUPPORTED(fmi3ActivateModelPartition, "scheduled execution: " MODEL_IDENTIFIER
                " supports co-simulation only");
}
