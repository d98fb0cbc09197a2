/* Backend of fmi2.c: pythonfmu 0.7's stock wrapper, shipped beside the FMU's binary as
 * WRAPPED_LIBRARY (config.h), which runs the Python slave.
 *
 * - The status of a call is the worst status the Python slave logged during it:
 *   pythonfmu's wrapper can only answer OK, Discard or Fatal from Python, so this is how
 *   exitInitializationMode answers fmi2Error for an invalid parameter set and doStep
 *   fmi2Warning for inputs that cannot be solved.
 * - The wrapper frees its Python objects when it raises fmi2Fatal: such an instance is
 *   never handed back to it (not even to be freed).
 * - Python is initialised here with an error status instead of the interpreter's process
 *   exit when the host has none (with Python's headers at build time).
 */
#include <dlfcn.h>

#ifdef GUARD_PYTHON_INIT
#include <Python.h>
#endif

typedef struct {
    fmi2InstantiateTYPE *Instantiate;
    fmi2FreeInstanceTYPE *FreeInstance;
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

typedef struct {
    fmi2CallbackFunctions to_wrapped; /* ours, handed to the wrapper (it keeps the pointer) */
    fmi2Component inner;
    fmi2Status worst; /* worst status the slave logged in the current call */
    Instance *in;
    int failed;
} Slave;

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
    RESOLVE(Instantiate) RESOLVE(FreeInstance) RESOLVE(SetupExperiment)
    RESOLVE(EnterInitializationMode) RESOLVE(ExitInitializationMode) RESOLVE(Terminate)
    RESOLVE(Reset) RESOLVE(GetReal) RESOLVE(GetInteger) RESOLVE(GetBoolean) RESOLVE(GetString)
    RESOLVE(SetReal) RESOLVE(SetInteger) RESOLVE(SetBoolean) RESOLVE(SetString)
    RESOLVE(GetFMUstate) RESOLVE(SetFMUstate) RESOLVE(FreeFMUstate)
    RESOLVE(SerializedFMUstateSize) RESOLVE(SerializeFMUstate) RESOLVE(DeSerializeFMUstate)
    RESOLVE(DoStep)
#undef RESOLVE
    wrapped.finalize = (void (*)(void))dlsym(lib, "finalizePythonInterpreter");
    atexit(release_wrapper);
    wrapped_loaded = 1;
    return 1;
}

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

static int backend_ready(char *why, size_t size) {
    if (!load_wrapped()) {
        snprintf(why, size, "%s", wrapped_error);
        return 0;
    }
    return python_ready(why, size);
}

/* The wrapper's logger: note the worst status of the call, forward what is not empty.
 * The wrapper passes the text as the format without arguments; the slave escapes '%'. */
static void from_wrapped(fmi2ComponentEnvironment env, fmi2String instance, fmi2Status status,
                         fmi2String category, fmi2String message, ...) {
    (void)instance;
    Slave *sl = (Slave *)env;
    if (!sl) return;
    if (status > sl->worst) sl->worst = status;
    if (!message || !*message) return; /* a status without a message (a counted repeat) */
    if (status == fmi2Fatal) status = fmi2Error; /* the guard's answer, not the wrapper's */
    const Instance *in = sl->in;
    if (in->host.logger && category_enabled(in, status, category))
        in->host.logger(in->host.componentEnvironment, in->name, status, category, message);
}

static void *backend_instantiate(Instance *in, fmi2String guid, fmi2String resources,
                                 fmi2Boolean visible) {
    Slave *sl = (Slave *)in->host.allocateMemory(1, sizeof *sl);
    if (!sl) {
        say(in, fmi2Error, "fmi2Instantiate: out of memory");
        return NULL;
    }
    sl->in = in;
    sl->to_wrapped = in->host;
    sl->to_wrapped.logger = from_wrapped;
    sl->to_wrapped.componentEnvironment = sl;
    /* the wrapper logs nothing unless logging is on: it is always on towards the guard,
     * which filters by the host's settings */
    sl->inner = wrapped.Instantiate(in->name, fmi2CoSimulation, guid, resources,
                                    &sl->to_wrapped, visible, fmi2True);
    if (!sl->inner) {
        say(in, fmi2Error, "fmi2Instantiate: pythonfmu's wrapper could not create the slave");
        in->host.freeMemory(sl);
        return NULL;
    }
    return sl;
}

static void backend_free(Instance *in) {
    Slave *sl = (Slave *)in->model;
    /* a failed instance is left to the wrapper's freed objects: freeing it would free them
     * again */
    if (!sl->failed) wrapped.FreeInstance(sl->inner);
    in->host.freeMemory(sl);
}

/* Around a call of the wrapper: its answer is the worst of its status and what the slave
 * logged meanwhile. A wrapper Fatal (a Python exception) fails the instance for good. */
static Slave *begin(Instance *in) {
    Slave *sl = (Slave *)in->model;
    sl->worst = fmi2OK;
    return sl;
}

static fmi2Status finish(Instance *in, fmi2Status status) {
    Slave *sl = (Slave *)in->model;
    if (status == fmi2Fatal || sl->worst == fmi2Fatal) {
        sl->failed = 1;
        say(in, fmi2Error, "the Python slave raised");
        return fmi2Fatal;
    }
    return sl->worst > status ? sl->worst : status;
}

static fmi2Status backend_setup_experiment(Instance *in, fmi2Boolean tolerance_defined,
                                           fmi2Real tolerance, fmi2Real start,
                                           fmi2Boolean stop_defined, fmi2Real stop) {
    Slave *sl = begin(in);
    return finish(in, wrapped.SetupExperiment(sl->inner, tolerance_defined, tolerance, start,
                                              stop_defined, stop));
}
static fmi2Status backend_enter_initialization(Instance *in) {
    Slave *sl = begin(in);
    return finish(in, wrapped.EnterInitializationMode(sl->inner));
}
static fmi2Status backend_exit_initialization(Instance *in) {
    Slave *sl = begin(in);
    return finish(in, wrapped.ExitInitializationMode(sl->inner));
}
static fmi2Status backend_terminate(Instance *in) {
    Slave *sl = begin(in);
    return finish(in, wrapped.Terminate(sl->inner));
}
static fmi2Status backend_reset(Instance *in) {
    Slave *sl = begin(in);
    return finish(in, wrapped.Reset(sl->inner));
}

#define ACCESS(name, Name, ctype)                                                          \
    static fmi2Status backend_get_##name(Instance *in, const fmi2ValueReference vr[],      \
                                         size_t n, ctype value[]) {                        \
        Slave *sl = begin(in);                                                             \
        return finish(in, wrapped.Get##Name(sl->inner, vr, n, value));                     \
    }                                                                                      \
    static fmi2Status backend_set_##name(Instance *in, const fmi2ValueReference vr[],      \
                                         size_t n, const ctype value[]) {                  \
        Slave *sl = begin(in);                                                             \
        return finish(in, wrapped.Set##Name(sl->inner, vr, n, value));                     \
    }
ACCESS(real, Real, fmi2Real)
ACCESS(integer, Integer, fmi2Integer)
ACCESS(boolean, Boolean, fmi2Boolean)
ACCESS(string, String, fmi2String)

static fmi2Status backend_do_step(Instance *in, fmi2Real t, fmi2Real h, fmi2Boolean no_set) {
    Slave *sl = begin(in);
    return finish(in, wrapped.DoStep(sl->inner, t, h, no_set));
}

static fmi2Status backend_get_state(Instance *in, void **state) {
    Slave *sl = begin(in);
    fmi2FMUstate inner = NULL;
    fmi2Status s = finish(in, wrapped.GetFMUstate(sl->inner, &inner));
    if (s > fmi2Warning || !inner) return s;
    if (*state) wrapped.FreeFMUstate(sl->inner, state);
    *state = inner;
    return s;
}

static fmi2Status backend_set_state(Instance *in, void *state) {
    Slave *sl = begin(in);
    return finish(in, wrapped.SetFMUstate(sl->inner, state));
}

static void backend_free_state(Instance *in, void *state) {
    Slave *sl = (Slave *)in->model;
    if (!sl->failed) wrapped.FreeFMUstate(sl->inner, &state);
}

static fmi2Status backend_state_size(Instance *in, void *state, size_t *size) {
    Slave *sl = begin(in);
    return finish(in, wrapped.SerializedFMUstateSize(sl->inner, state, size));
}

static fmi2Status backend_serialize(Instance *in, void *state, unsigned char *bytes, size_t n) {
    Slave *sl = begin(in);
    return finish(in, wrapped.SerializeFMUstate(sl->inner, state, (fmi2Byte *)bytes, n));
}

static fmi2Status backend_deserialize(Instance *in, const unsigned char *bytes, size_t n,
                                      void **state) {
    Slave *sl = begin(in);
    fmi2FMUstate inner = NULL;
    fmi2Status s = finish(in, wrapped.DeSerializeFMUstate(sl->inner, (const fmi2Byte *)bytes, n,
                                                          &inner));
    *state = inner;
    return s;
}
