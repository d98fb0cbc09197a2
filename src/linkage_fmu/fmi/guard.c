/* FMI 2.0 co-simulation guard in front of pythonfmu 0.7's wrapper.
 *
 * The FMU's binary is this file compiled with a generated `guard_config.h` (the model's
 * identifier, GUID and variable table). It loads pythonfmu's stock wrapper, shipped
 * beside it as WRAPPED_LIBRARY, and forwards to it only calls that are valid:
 *
 * - every argument is checked before any state changes: null pointers, unknown value
 *   references, wrong types, variables that may not be set in the current state (fixed
 *   parameters after initialisation, outputs), strings that are not UTF-8, step sizes
 *   and times that are not finite and positive; a bad call is fmi2Error with a log
 *   naming the call, the reference and the reason, and the instance stays usable;
 * - the co-simulation state machine of FMI 2.0 is enforced here;
 * - the status of a forwarded call is the worst status the Python slave logged during
 *   it (pythonfmu's wrapper can only answer OK, Discard or Fatal from Python): that is
 *   how exitInitializationMode answers fmi2Error for an invalid parameter set and doStep
 *   fmi2Warning for inputs that cannot be solved;
 * - fmi2Fatal never reaches the host: the wrapper frees its Python objects when it
 *   raises one, so the instance is marked failed, answers fmi2Error from then on, and is
 *   never handed back to the wrapper (not even to be freed);
 * - fmi2GetBooleanStatus(fmi2Terminated) and fmi2GetRealStatus(fmi2LastSuccessfulTime)
 *   are answered here (the wrapper's terminate flag, once set, stays set);
 * - serialized states carry a header (model identifier, GUID, format version, length,
 *   CRC-32): a foreign or corrupted state is rejected with fmi2Error;
 * - the GUID passed to fmi2Instantiate must match; Python is initialised here with an
 *   error status instead of the interpreter's process exit when the host has none.
 */
#define _GNU_SOURCE /* dladdr */
#include <dlfcn.h>
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
} Variable;

#include "guard_config.h"

#ifdef GUARD_PYTHON_INIT
#include <Python.h>
#endif

/* identity of this model's states in memory: the address is unique to this binary */
static const char THIS_MODEL[] = MODEL_GUID;

#define STATE_FORMAT 1u
static const char STATE_MAGIC[8] = {'L', 'K', 'F', 'M', 'U', 'S', 'T', '\0'};

typedef enum { S_INSTANTIATED, S_INIT, S_STEP, S_TERMINATED, S_FAILED } Machine;
static const char *MACHINE_NAMES[] = {"Instantiated", "InitializationMode", "StepComplete",
                                      "Terminated", "failed"};

/* -- the wrapped library ---------------------------------------------------------------- */
typedef struct {
    fmi2InstantiateTYPE *Instantiate;
    fmi2FreeInstanceTYPE *FreeInstance;
    fmi2SetDebugLoggingTYPE *SetDebugLogging;
    fmi2SetupExperimentTYPE *SetupExperiment;
    fmi2EnterInitializationModeTYPE *EnterInitializationMode;
    fmi2ExitInitializationModeTYPE *ExitInitializationMode;
    fmi2TerminateTYPE *Terminate;
    fmi2ResetTYPE *Reset;
    fmi2GetRealTYPE *GetReal;
    fmi2GetIntegerTYPE *GetInteger;
    fmi2GetBooleanTYPE *GetBoolean;
    fmi2GetStringTYPE *GetString;
    fmi2SetRealTYPE *SetReal;
    fmi2SetIntegerTYPE *SetInteger;
    fmi2SetBooleanTYPE *SetBoolean;
    fmi2SetStringTYPE *SetString;
    fmi2GetFMUstateTYPE *GetFMUstate;
    fmi2SetFMUstateTYPE *SetFMUstate;
    fmi2FreeFMUstateTYPE *FreeFMUstate;
    fmi2SerializedFMUstateSizeTYPE *SerializedFMUstateSize;
    fmi2SerializeFMUstateTYPE *SerializeFMUstate;
    fmi2DeSerializeFMUstateTYPE *DeSerializeFMUstate;
    fmi2DoStepTYPE *DoStep;
    void (*finalize)(void);
} Wrapped;

static Wrapped wrapped;  /* resolved once per process; the library is never unloaded */
static int wrapped_loaded = 0;
static char wrapped_error[PATH_MAX + 512];

/* The wrapper's interpreter state is a static shared_ptr that the C++ runtime destroys at
 * exit and its own destructor function releases again: a double free. Releasing it first,
 * from a handler registered after the wrapper was loaded (so it runs before the wrapper's
 * own exit-time destructors), leaves both later releases with an empty pointer. */
static void release_wrapper(void) {
    if (wrapped.finalize) wrapped.finalize();
}

static int load_wrapped(void) {
    if (wrapped_loaded) return 1;
    Dl_info info;
    if (!dladdr((void *)&load_wrapped, &info) || !info.dli_fname) {
        snprintf(wrapped_error, sizeof wrapped_error, "cannot find this FMU's binary");
        return 0;
    }
    char path[PATH_MAX];
    const char *slash = strrchr(info.dli_fname, '/');
    size_t dir = slash ? (size_t)(slash - info.dli_fname + 1) : 0;
    if (dir + strlen(WRAPPED_LIBRARY) + 1 > sizeof path) {
        snprintf(wrapped_error, sizeof wrapped_error, "path of this FMU's binary is too long");
        return 0;
    }
    memcpy(path, info.dli_fname, dir);
    strcpy(path + dir, WRAPPED_LIBRARY);
    void *lib = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!lib) {
        snprintf(wrapped_error, sizeof wrapped_error,
                 "cannot load pythonfmu's wrapper (%s); it needs libpython " PYTHON_VERSION
                 " loaded in the importing process: %s",
                 path, dlerror());
        return 0;
    }
#define RESOLVE(name)                                                                      \
    if (!(wrapped.name = (fmi2##name##TYPE *)dlsym(lib, "fmi2" #name))) {                  \
        snprintf(wrapped_error, sizeof wrapped_error, "%s has no fmi2" #name, path);       \
        return 0;                                                                          \
    }
    RESOLVE(Instantiate) RESOLVE(FreeInstance) RESOLVE(SetDebugLogging)
    RESOLVE(SetupExperiment) RESOLVE(EnterInitializationMode) RESOLVE(ExitInitializationMode)
    RESOLVE(Terminate) RESOLVE(Reset) RESOLVE(GetReal) RESOLVE(GetInteger) RESOLVE(GetBoolean)
    RESOLVE(GetString) RESOLVE(SetReal) RESOLVE(SetInteger) RESOLVE(SetBoolean)
    RESOLVE(SetString) RESOLVE(GetFMUstate) RESOLVE(SetFMUstate) RESOLVE(FreeFMUstate)
    RESOLVE(SerializedFMUstateSize) RESOLVE(SerializeFMUstate) RESOLVE(DeSerializeFMUstate)
    RESOLVE(DoStep)
#undef RESOLVE
    wrapped.finalize = (void (*)(void))dlsym(lib, "finalizePythonInterpreter");
    atexit(release_wrapper);
    wrapped_loaded = 1;
    return 1;
}

/* -- instances -------------------------------------------------------------------------- */
typedef struct {
    char *name;
    fmi2CallbackFunctions host;        /* the importer's callbacks */
    fmi2CallbackFunctions to_wrapped;  /* ours, handed to the wrapper (it keeps the pointer) */
    fmi2Component inner;
    Machine machine;
    fmi2Boolean logging;
    unsigned categories;               /* bit i: LOG_CATEGORIES[i] enabled; 0 = all */
    fmi2Status worst;                  /* worst status the slave logged in the current call */
    double time;
} Instance;

typedef struct {
    char magic[8];
    const char *guid;
    double time;
    fmi2FMUstate inner;
} SavedState;

static const char *LOG_CATEGORIES[] = {"logStatusWarning", "logStatusDiscard",
                                       "logStatusError", "logStatusFatal", "logAll"};
#define N_CATEGORIES (sizeof LOG_CATEGORIES / sizeof *LOG_CATEGORIES)

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

/* Log a message of this guard (printf-style) with `status`, and return `status`. */
static fmi2Status say(const Instance *in, fmi2Status status, const char *fmt, ...) {
    char text[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    emit(in, status, status >= fmi2Error ? "logStatusError" : "logStatusWarning", text);
    return status;
}

/* The wrapper's logger: note the worst status of the call, forward what is not empty.
 * The wrapper passes the text as the format without arguments; the slave escapes '%'. */
static void from_wrapped(fmi2ComponentEnvironment env, fmi2String instance, fmi2Status status,
                         fmi2String category, fmi2String message, ...) {
    (void)instance;
    Instance *in = (Instance *)env;
    if (!in) return;
    if (status > in->worst) in->worst = status;
    if (!message || !*message) return; /* a status without a message (a counted repeat) */
    if (status == fmi2Fatal) status = fmi2Error; /* the guard's answer, not the wrapper's */
    if (in->host.logger && category_enabled(in, status, category))
        in->host.logger(in->host.componentEnvironment, in->name, status, category, message);
}

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

/* Begin a forwarded call. */
static void start(Instance *in) { in->worst = fmi2OK; }

/* End a forwarded call: the worst of the wrapper's status and what the slave logged.
 * A wrapper Fatal (a Python exception) fails the instance for good. */
static fmi2Status finish(Instance *in, const char *call, fmi2Status status) {
    if (status == fmi2Fatal || in->worst == fmi2Fatal) {
        in->machine = S_FAILED;
        return say(in, fmi2Error, "%s: the Python slave raised; this instance can only be freed",
                   call);
    }
    if (status == fmi2Pending) status = fmi2Error;
    return in->worst > status ? in->worst : status;
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

/* 1 if `s` is well-formed UTF-8 (what the slave's Python strings must be). */
static int utf8(const unsigned char *s) {
    while (*s) {
        unsigned c = *s++, n;
        uint32_t cp;
        if (c < 0x80) continue;
        if (c >= 0xC2 && c <= 0xDF) n = 1, cp = c & 0x1F;
        else if (c >= 0xE0 && c <= 0xEF) n = 2, cp = c & 0x0F;
        else if (c >= 0xF0 && c <= 0xF4) n = 3, cp = c & 0x07;
        else return 0;
        for (unsigned k = 0; k < n; k++, s++) {
            if ((*s & 0xC0) != 0x80) return 0;
            cp = cp << 6 | (*s & 0x3F);
        }
        if ((n == 2 && cp < 0x800) || (n == 3 && (cp < 0x10000 || cp > 0x10FFFF)) ||
            (cp >= 0xD800 && cp <= 0xDFFF))
            return 0;
    }
    return 1;
}

/* -- Python ----------------------------------------------------------------------------- */
/* Start the interpreter here if the host has none: Py_InitializeFromConfig reports a bad
 * PYTHONHOME as a status, where the wrapper's Py_Initialize would exit the process. The
 * functions are looked up in the process (the wrapper needs libpython there anyway), so
 * this binary does not link libpython. */
static int python_ready(char *why, size_t size) {
#ifdef GUARD_PYTHON_INIT
    int (*is_initialized)(void) = (int (*)(void))dlsym(RTLD_DEFAULT, "Py_IsInitialized");
    void (*init_config)(PyConfig *) =
        (void (*)(PyConfig *))dlsym(RTLD_DEFAULT, "PyConfig_InitPythonConfig");
    PyStatus (*initialize)(const PyConfig *) =
        (PyStatus(*)(const PyConfig *))dlsym(RTLD_DEFAULT, "Py_InitializeFromConfig");
    void (*clear)(PyConfig *) = (void (*)(PyConfig *))dlsym(RTLD_DEFAULT, "PyConfig_Clear");
    int (*failed)(PyStatus) = (int (*)(PyStatus))dlsym(RTLD_DEFAULT, "PyStatus_Exception");
    void *(*save_thread)(void) = (void *(*)(void))dlsym(RTLD_DEFAULT, "PyEval_SaveThread");
    if (!is_initialized || !init_config || !initialize || !clear || !failed || !save_thread) {
        snprintf(why, size, "libpython " PYTHON_VERSION " is not loaded in this process");
        return 0;
    }
    if (is_initialized()) return 1;
    PyConfig config;
    init_config(&config);
    PyStatus status = initialize(&config);
    clear(&config);
    if (failed(status)) {
        snprintf(why, size, "cannot start Python " PYTHON_VERSION " (check PYTHONHOME and "
                 "PYTHONPATH): %s%s%s", status.func ? status.func : "",
                 status.func ? ": " : "", status.err_msg ? status.err_msg : "unknown error");
        return 0;
    }
    save_thread(); /* the wrapper takes the GIL per call */
#else
    (void)why;
    (void)size;
#endif
    return 1;
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
    else if (!load_wrapped())
        snprintf(why, sizeof why, "%s", wrapped_error);
    else
        python_ready(why, sizeof why);
    if (why[0]) {
        say(&probe, fmi2Error, "fmi2Instantiate: %s", why);
        return NULL;
    }
    Instance *in = (Instance *)functions->allocateMemory(1, sizeof *in);
    char *name = (char *)functions->allocateMemory(strlen(instanceName) + 1, 1);
    if (!in || !name) {
        if (in) functions->freeMemory(in);
        say(&probe, fmi2Error, "fmi2Instantiate: out of memory");
        return NULL;
    }
    strcpy(name, instanceName);
    *in = probe;
    in->name = name;
    in->to_wrapped = *functions;
    in->to_wrapped.logger = from_wrapped;
    in->to_wrapped.componentEnvironment = in;
    in->machine = S_INSTANTIATED;
    /* the wrapper logs nothing unless logging is on: it is always on towards the guard,
     * which filters by the host's settings */
    in->inner = wrapped.Instantiate(instanceName, fmuType, fmuGUID, fmuResourceLocation,
                                    &in->to_wrapped, visible, fmi2True);
    if (!in->inner) {
        say(in, fmi2Error, "fmi2Instantiate: pythonfmu's wrapper could not create the slave");
        functions->freeMemory(name);
        functions->freeMemory(in);
        return NULL;
    }
    return in;
}

void fmi2FreeInstance(fmi2Component c) {
    Instance *in = (Instance *)c;
    if (!in) return;
    /* a failed instance is left to the wrapper's freed objects: freeing it would free them
     * again */
    if (in->machine != S_FAILED) wrapped.FreeInstance(in->inner);
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
    start(in);
    fmi2Status s = finish(in, "fmi2SetupExperiment",
                          wrapped.SetupExperiment(in->inner, toleranceDefined, tolerance, startTime,
                                                  stopTimeDefined, stopTime));
    if (s <= fmi2Warning) in->time = startTime;
    return s;
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c) {
    INSTANCE(c, "fmi2EnterInitializationMode");
    if (require(in, "fmi2EnterInitializationMode", IN(S_INSTANTIATED))) return fmi2Error;
    start(in);
    fmi2Status s = finish(in, "fmi2EnterInitializationMode",
                          wrapped.EnterInitializationMode(in->inner));
    if (s <= fmi2Warning) in->machine = S_INIT;
    return s;
}

fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
    INSTANCE(c, "fmi2ExitInitializationMode");
    if (require(in, "fmi2ExitInitializationMode", IN(S_INIT))) return fmi2Error;
    start(in);
    fmi2Status s = finish(in, "fmi2ExitInitializationMode",
                          wrapped.ExitInitializationMode(in->inner));
    /* an invalid parameter set leaves the instance in initialisation mode, to be fixed */
    if (s <= fmi2Warning) in->machine = S_STEP;
    return s;
}

fmi2Status fmi2Terminate(fmi2Component c) {
    INSTANCE(c, "fmi2Terminate");
    if (require(in, "fmi2Terminate", IN(S_STEP))) return fmi2Error;
    start(in);
    fmi2Status s = finish(in, "fmi2Terminate", wrapped.Terminate(in->inner));
    if (s <= fmi2Warning) in->machine = S_TERMINATED;
    return s;
}

fmi2Status fmi2Reset(fmi2Component c) {
    INSTANCE(c, "fmi2Reset");
    start(in);
    fmi2Status s = finish(in, "fmi2Reset", wrapped.Reset(in->inner));
    if (s <= fmi2Warning) {
        in->machine = S_INSTANTIATED;
        in->time = 0.0;
    }
    return s;
}

/* -- values ----------------------------------------------------------------------------- */
#define READABLE (IN(S_INIT) | IN(S_STEP) | IN(S_TERMINATED))
#define WRITABLE (IN(S_INSTANTIATED) | IN(S_INIT) | IN(S_STEP))

#define GETTER(Name, ctype, type)                                                          \
    fmi2Status fmi2Get##Name(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,    \
                             ctype value[]) {                                              \
        INSTANCE(c, "fmi2Get" #Name);                                                      \
        if (require(in, "fmi2Get" #Name, READABLE) ||                                      \
            check_refs(in, "fmi2Get" #Name, vr, nvr, value, type))                         \
            return fmi2Error;                                                              \
        if (nvr == 0) return fmi2OK;                                                       \
        start(in);                                                                         \
        return finish(in, "fmi2Get" #Name, wrapped.Get##Name(in->inner, vr, nvr, value));  \
    }
GETTER(Real, fmi2Real, T_REAL)
GETTER(Integer, fmi2Integer, T_INTEGER)
GETTER(Boolean, fmi2Boolean, T_BOOLEAN)
GETTER(String, fmi2String, T_STRING)

#define SETTER(Name, ctype, type, extra)                                                   \
    fmi2Status fmi2Set##Name(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,    \
                             const ctype value[]) {                                        \
        INSTANCE(c, "fmi2Set" #Name);                                                      \
        if (require(in, "fmi2Set" #Name, WRITABLE) ||                                      \
            check_refs(in, "fmi2Set" #Name, vr, nvr, value, type) ||                       \
            check_settable(in, "fmi2Set" #Name, vr, nvr))                                  \
            return fmi2Error;                                                              \
        extra;                                                                             \
        if (nvr == 0) return fmi2OK;                                                       \
        start(in);                                                                         \
        return finish(in, "fmi2Set" #Name, wrapped.Set##Name(in->inner, vr, nvr, value));  \
    }
SETTER(Real, fmi2Real, T_REAL, )
SETTER(Integer, fmi2Integer, T_INTEGER, )
SETTER(Boolean, fmi2Boolean, T_BOOLEAN,
       for (size_t i = 0; i < nvr; i++) if (value[i] != fmi2True && value[i] != fmi2False)
           return say(in, fmi2Error, "fmi2SetBoolean: value %d for '%s' is neither fmi2True "
                      "nor fmi2False", (int)value[i], VARIABLES[vr[i]].name))
SETTER(String, fmi2String, T_STRING,
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
    start(in);
    fmi2Status s = finish(in, "fmi2DoStep",
                          wrapped.DoStep(in->inner, currentCommunicationPoint,
                                         communicationStepSize, noSetFMUStatePriorToCurrentPoint));
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
    *value = fmi2False; /* the slave never asks the master to end the run */
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
    fmi2FMUstate inner = NULL;
    start(in);
    fmi2Status status = finish(in, "fmi2GetFMUstate", wrapped.GetFMUstate(in->inner, &inner));
    if (status > fmi2Warning || !inner) {
        if (!*state) in->host.freeMemory(s);
        return status > fmi2Warning ? status : say(in, fmi2Error, "fmi2GetFMUstate: no state");
    }
    if (*state && s->inner) wrapped.FreeFMUstate(in->inner, &s->inner);
    memcpy(s->magic, STATE_MAGIC, sizeof STATE_MAGIC);
    s->guid = THIS_MODEL;
    s->time = in->time;
    s->inner = inner;
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
    start(in);
    fmi2Status status = finish(in, "fmi2SetFMUstate", wrapped.SetFMUstate(in->inner, s->inner));
    if (status <= fmi2Warning) in->time = s->time;
    return status;
}

fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *state) {
    INSTANCE(c, "fmi2FreeFMUstate");
    if (!state) return say(in, fmi2Error, "fmi2FreeFMUstate: the state pointer is NULL");
    if (!*state) return fmi2OK;
    SavedState *s = saved(in, "fmi2FreeFMUstate", *state);
    if (!s) return fmi2Error;
    wrapped.FreeFMUstate(in->inner, &s->inner);
    memset(s->magic, 0, sizeof s->magic);
    in->host.freeMemory(s);
    *state = NULL;
    return fmi2OK;
}

/* Serialized layout: magic[8] | u32 format | u32 nid | id | u32 nguid | guid | f64 time |
 * u64 n | payload[n] (the wrapper's) | u32 CRC-32 of all bytes before it. */
static uint32_t crc32(const unsigned char *p, size_t n) {
    uint32_t crc = 0xFFFFFFFFu;
    while (n--) {
        crc ^= *p++;
        for (int k = 0; k < 8; k++) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
    }
    return ~crc;
}

static size_t header_size(void) {
    return 8 + 4 + 4 + strlen(MODEL_IDENTIFIER) + 4 + strlen(MODEL_GUID) + 8 + 8;
}

fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate state, size_t *size) {
    INSTANCE(c, "fmi2SerializedFMUstateSize");
    if (!size) return say(in, fmi2Error, "fmi2SerializedFMUstateSize: size is NULL");
    SavedState *s = saved(in, "fmi2SerializedFMUstateSize", state);
    if (!s) return fmi2Error;
    size_t n = 0;
    start(in);
    fmi2Status status = finish(in, "fmi2SerializedFMUstateSize",
                               wrapped.SerializedFMUstateSize(in->inner, s->inner, &n));
    if (status <= fmi2Warning) *size = header_size() + n + 4;
    return status;
}

static unsigned char *put(unsigned char *p, const void *v, size_t n) {
    memcpy(p, v, n);
    return p + n;
}

fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate state, fmi2Byte bytes[],
                                 size_t size) {
    INSTANCE(c, "fmi2SerializeFMUstate");
    SavedState *s = saved(in, "fmi2SerializeFMUstate", state);
    if (!s) return fmi2Error;
    if (!bytes) return say(in, fmi2Error, "fmi2SerializeFMUstate: bytes is NULL");
    size_t n = 0;
    start(in);
    fmi2Status status = finish(in, "fmi2SerializeFMUstate",
                               wrapped.SerializedFMUstateSize(in->inner, s->inner, &n));
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
    start(in);
    status = finish(in, "fmi2SerializeFMUstate",
                    wrapped.SerializeFMUstate(in->inner, s->inner, (fmi2Byte *)p, n));
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
    fmi2FMUstate inner = NULL;
    start(in);
    fmi2Status status = finish(in, call, wrapped.DeSerializeFMUstate(
                                             in->inner, (const fmi2Byte *)(b + head), (size_t)n,
                                             &inner));
    if (status > fmi2Warning || !inner) {
        in->host.freeMemory(s);
        return status > fmi2Warning ? status : say(in, fmi2Error, "%s: no state", call);
    }
    memcpy(s->magic, STATE_MAGIC, sizeof STATE_MAGIC);
    s->guid = THIS_MODEL;
    s->time = time;
    s->inner = inner;
    *state = s;
    return status;
}
