/* The pythonfmu backend of framework.c: the package's own solver, in the importing
 * process's Python, through pythonfmu 0.7's stock wrapper (WRAPPED_LIBRARY beside this
 * binary, an FMI 2.0 library), which runs the Python slave (linkage_fmu.fmi.slave).
 *
 * The framework owns the values and the policy; the slave only computes:
 * - a prepare sets every parameter in the slave and calls ExitInitializationMode, where
 *   the slave builds the linkage (an invalid set: it logs why, with fmi2Error);
 * - an evaluation sets the inputs and reads every output with one GetReal: the slave
 *   solves once (a state it cannot solve: NaN, and it logs why with fmi2Discard).
 * The slave's logs reach this backend only (their words become the framework's), and the
 * status of a call is the worst of the wrapper's and what the slave logged: the wrapper
 * itself answers only OK, Discard or Fatal.
 *
 * The wrapper's defects this backend works around: it turns the resource location into a
 * path by cutting "file://" and decoding "%20" only, and crashes the host on any other
 * form or on a folder without the slave (the framework decodes the URI; this backend
 * checks the folder and hands the wrapper a plain path); it frees its Python objects when
 * it answers Fatal, so such an instance is never handed back to it; it frees its
 * interpreter state twice at exit (released first here); it starts Python with
 * Py_Initialize, which exits the process on a bad PYTHONHOME (started here instead); and
 * every instantiation keeps about a kilobyte the wrapper never frees (it runs the slave
 * script again and leaks what it makes of it), so a freed instance's slave is kept and
 * given to the next instance of this binary, which sets every value it uses afresh:
 * instantiate/free cycles keep no memory. The kept slaves are freed when the binary is
 * unloaded, while Python runs.
 */
#include <dlfcn.h>
#include <pthread.h>

#include "fmi2FunctionTypes.h"

#ifdef GUARD_PYTHON_INIT
#include <Python.h>
#endif

typedef struct {
    fmi2InstantiateTYPE *Instantiate;
    fmi2FreeInstanceTYPE *FreeInstance;
    fmi2ExitInitializationModeTYPE *ExitInitializationMode;
    fmi2GetRealTYPE *GetReal;
    fmi2SetRealTYPE *SetReal;
    fmi2SetIntegerTYPE *SetInteger;
    fmi2SetStringTYPE *SetString;
    void (*finalize)(void);
} Wrapped;

static Wrapped wrapped; /* resolved once per process; the library is never unloaded */
static int wrapped_loaded = 0;
static char wrapped_error[LK_PATH + 512];

typedef struct Slave {
    fmi2CallbackFunctions to_wrapped; /* ours, handed to the wrapper (it keeps the pointer) */
    fmi2Component inner;
    Status worst;    /* the worst status the slave logged in the current call */
    char said[1024]; /* ... and what it said with it */
    int failed;      /* the wrapper answered Fatal: never call it again for this instance */
    struct Slave *next; /* in the pool of slaves of freed instances */
} Slave;

static pthread_mutex_t pool_lock = PTHREAD_MUTEX_INITIALIZER;
static Slave *pool = NULL; /* slaves of freed instances, for the next instances */

/* The wrapper's interpreter state is a static shared_ptr that the C++ runtime destroys at
 * exit and its own destructor function releases again: a double free. Releasing it first,
 * from a handler registered after the wrapper was loaded (so it runs before the wrapper's
 * own exit-time destructors), leaves both later releases with an empty pointer. */
static void release_wrapper(void) {
    int (*running)(void) = (int (*)(void))dlsym(RTLD_DEFAULT, "Py_IsInitialized");
    pthread_mutex_lock(&pool_lock);
    while (pool) { /* unloaded while Python runs: free the kept slaves (at exit: not) */
        Slave *sl = pool;
        pool = sl->next;
        if (running && running()) wrapped.FreeInstance(sl->inner);
        free(sl);
    }
    pthread_mutex_unlock(&pool_lock);
    if (wrapped.finalize) wrapped.finalize();
}

static int load_wrapped(void) {
    if (wrapped_loaded) return 1;
    Dl_info info;
    if (!dladdr((void *)&load_wrapped, &info) || !info.dli_fname) {
        set_text(wrapped_error, sizeof wrapped_error, "cannot find this FMU's binary");
        return 0;
    }
    char path[LK_PATH];
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
                 " loaded in the importing process: %s", path, dlerror());
        return 0;
    }
#define RESOLVE(name)                                                                      \
    if (!(wrapped.name = (fmi2##name##TYPE *)dlsym(lib, "fmi2" #name))) {                  \
        snprintf(wrapped_error, sizeof wrapped_error, "%s has no fmi2" #name, path);       \
        return 0;                                                                          \
    }
    RESOLVE(Instantiate) RESOLVE(FreeInstance) RESOLVE(ExitInitializationMode)
    RESOLVE(GetReal) RESOLVE(SetReal) RESOLVE(SetInteger) RESOLVE(SetString)
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
        set_text(why, size, wrapped_error);
        return 0;
    }
    return python_ready(why, size);
}

/* The wrapper's logger: keep the worst status of the call and what the slave said with
 * it; nothing reaches the host from here (the framework says it, in its own words). */
static void from_wrapped(fmi2ComponentEnvironment env, fmi2String instance, fmi2Status status,
                         fmi2String category, fmi2String message, ...) {
    (void)instance, (void)category;
    Slave *sl = (Slave *)env;
    if (!sl) return;
    if ((Status)status >= sl->worst && message && *message)
        set_text(sl->said, sizeof sl->said, message);
    if ((Status)status > sl->worst) sl->worst = (Status)status;
}

/* 1 if `path/name` can be opened for reading. */
static int readable(const char *path, const char *name) {
    char file[LK_PATH + 64];
    if ((size_t)snprintf(file, sizeof file, "%s/%s", path, name) >= sizeof file) return 0;
    FILE *f = fopen(file, "rb");
    if (f) fclose(f);
    return f != NULL;
}

static void *backend_instantiate(Instance *in, const char *resources, const char *location) {
    if (!resources) {
        say(in, LK_ERROR, "the resource location %s is not a file URI of an absolute path on "
            "this machine (file:///path, file:/path or file://localhost/path, %%XX escapes "
            "decoded) nor, for FMI 3.0, an absolute path", location ? location : "(null)");
        return NULL;
    }
    /* the wrapper rewrites these in a path; and it crashes on a folder without the slave */
    if (strstr(resources, "%20") || strstr(resources, "file://") ||
        !readable(resources, "slavemodule.txt") || !readable(resources, SLAVE_MODULE ".py")) {
        say(in, LK_ERROR, "the resource location %s is not the resources folder of "
            MODEL_IDENTIFIER " (no readable slavemodule.txt and " SLAVE_MODULE ".py in %s)",
            location, resources);
        return NULL;
    }
    pthread_mutex_lock(&pool_lock);
    Slave *sl = pool;
    if (sl) pool = sl->next;
    pthread_mutex_unlock(&pool_lock);
    if (sl) return sl; /* a freed instance's: the framework sets every value it uses */
    /* the wrapper keeps a pointer to the callbacks: memory of this binary's, not the host's */
    if (!(sl = (Slave *)calloc(1, sizeof *sl))) {
        say(in, LK_ERROR, "out of memory");
        return NULL;
    }
    sl->to_wrapped.logger = from_wrapped;
    sl->to_wrapped.allocateMemory = calloc;
    sl->to_wrapped.freeMemory = free;
    sl->to_wrapped.componentEnvironment = sl;
    /* the wrapper logs nothing unless logging is on: on towards this backend */
    sl->inner = wrapped.Instantiate(in->name, fmi2CoSimulation, MODEL_GUID, resources,
                                    &sl->to_wrapped, fmi2False, fmi2True);
    if (!sl->inner) {
        say(in, LK_ERROR, "pythonfmu's wrapper could not create the slave: %s",
            sl->said[0] ? sl->said : "no reason given");
        free(sl);
        return NULL;
    }
    return sl;
}

static void backend_free(Instance *in) {
    Slave *sl = (Slave *)in->model;
    if (sl->failed) { /* left to the wrapper's freed objects: freeing it would free them again */
        free(sl);
        return;
    }
    pthread_mutex_lock(&pool_lock);
    sl->next = pool;
    pool = sl;
    pthread_mutex_unlock(&pool_lock);
}

/* Around a call of the wrapper: the worst of its status and what the slave logged; a
 * Fatal (a Python exception) fails the slave for good. */
static Slave *begin(Instance *in) {
    Slave *sl = (Slave *)in->model;
    sl->worst = LK_OK;
    sl->said[0] = '\0';
    return sl;
}

static Status finish(Slave *sl, fmi2Status status, char *why, size_t size) {
    Status s = (Status)status > sl->worst ? (Status)status : sl->worst;
    if (s > LK_OK) set_text(why, size, sl->said[0] ? sl->said : "the Python slave failed");
    if (s == LK_FATAL) sl->failed = 1;
    return s;
}

static Status backend_prepare(Instance *in, const Values *v, char *why, size_t size) {
    Slave *sl = begin(in);
    fmi2ValueReference reals[N_VARIABLES], integers[N_VARIABLES], strings[N_VARIABLES];
    fmi2Real real[N_VARIABLES];
    fmi2Integer integer[N_VARIABLES];
    fmi2String string[N_VARIABLES];
    size_t nr = 0, ni = 0, ns = 0;
    for (unsigned vr = 0; vr < N_VARIABLES; vr++) {
        const Variable *var = &VARIABLES[vr];
        if (!var->name || var->kind != K_FIXED) continue;
        if (var->type == T_REAL) reals[nr] = vr, real[nr++] = v->real[vr];
        else if (var->type == T_INTEGER) integers[ni] = vr, integer[ni++] = v->integer[vr];
        else if (var->type == T_STRING) strings[ns] = vr, string[ns++] = v->string[vr];
    }
    fmi2Status s = wrapped.SetReal(sl->inner, reals, nr, real);
    if (s == fmi2OK) s = wrapped.SetInteger(sl->inner, integers, ni, integer);
    if (s == fmi2OK) s = wrapped.SetString(sl->inner, strings, ns, string);
    if (s == fmi2OK && sl->worst == LK_OK) s = wrapped.ExitInitializationMode(sl->inner);
    return finish(sl, s, why, size);
}

static Status backend_evaluate(Instance *in, const Values *v, double *y, char *why,
                               size_t size) {
    Slave *sl = begin(in);
    fmi2Real x[N_INPUTS + 1];
    for (int k = 0; k < N_INPUTS; k++) x[k] = v->real[INPUTS[k]];
    fmi2Status s = wrapped.SetReal(sl->inner, INPUTS, N_INPUTS, x);
    if (s == fmi2OK && sl->worst == LK_OK) s = wrapped.GetReal(sl->inner, OUTPUTS, N_OUTPUTS, y);
    Status status = finish(sl, s, why, size);
    return status == LK_WARNING ? LK_OK : status;
}
