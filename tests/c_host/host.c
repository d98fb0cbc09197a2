/* Minimal FMI 2.0 co-simulation host for the linkage FMUs (pythonfmu wrappers).
 *
 * usage: host DIR MODEL GUID N W L VR...
 *   DIR    unzipped FMU folder          MODEL  model identifier (DIR/binaries/linux64/MODEL.so)
 *   GUID   the guid of DIR/modelDescription.xml
 *   N      steps over one revolution    W, L   crank speed omega [rad/s] and load
 *   VR...  valueReferences of the Real outputs to print
 * Step k sets theta = 2*pi*k/N, omega = W, alpha = 0, load = L (valueReferences 0..3),
 * does one step and prints "theta,<outputs...>" to stdout; the wall time goes to stderr.
 *
 * build: gcc -std=c99 -O2 -Wall -Wextra -o host host.c -I<fmpy>/c-code -ldl
 * run:   LD_PRELOAD=<libpython.so> PYTHONPATH=<site-packages with numpy> ./host ...
 * The wrapper does not link libpython, so it must already be loaded globally.
 */
#define _XOPEN_SOURCE 700 /* realpath, clock_gettime, M_PI */
#include <dlfcn.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "fmi2Functions.h"

/* Worst status the FMU has logged. */
static fmi2Status worst_logged = fmi2OK;

/* Print the reason and stop at once, without tearing down an FMU left in an unknown state. */
static void die(const char *what, const char *detail) {
    fprintf(stderr, "%s: %s\n", what, detail ? detail : "");
    fflush(stdout);
    _Exit(1);
}

/* Stop on a status other than fmi2OK, or once an error was logged, naming the call. */
static void check(fmi2Status status, const char *call) {
    if (status == fmi2OK && worst_logged < fmi2Error) return;
    fprintf(stderr, "%s returned status %d (worst logged status %d)\n", call, (int)status,
            (int)worst_logged);
    fflush(stdout);
    _Exit(2);
}
#define CHECK(call) check((call), #call)

/* Resolve fmi2<name> from the shared library handle `lib` into a local `name`. */
#define LOAD(name)                                                             \
    fmi2##name##TYPE *name = (fmi2##name##TYPE *)dlsym(lib, "fmi2" #name);     \
    if (!name) die("missing symbol fmi2" #name, dlerror())

/* pythonfmu passes its log text as the format string without arguments, so it is
 * printed literally: a '%' in a Python message must not reach printf. */
static void logger(fmi2ComponentEnvironment env, fmi2String instance, fmi2Status status,
                   fmi2String category, fmi2String message, ...) {
    (void)env;
    if (status > worst_logged) worst_logged = status;
    fprintf(stderr, "[%s] status %d, %s: %s\n", instance, (int)status,
            category ? category : "-", message);
}

static double seconds(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

int main(int argc, char **argv) {
    if (argc < 8) die("usage", "host DIR MODEL GUID N W L VR...");
    char dir[PATH_MAX], path[PATH_MAX + 64], uri[PATH_MAX + 64];
    if (!realpath(argv[1], dir)) die("no such folder", argv[1]);
    const char *model = argv[2], *guid = argv[3];
    const int n = atoi(argv[4]);
    const double w = atof(argv[5]), load = atof(argv[6]);
    const size_t nout = (size_t)(argc - 7);
    if (n < 1 || !(w > 0)) die("N and W must be positive", NULL);

    fmi2ValueReference *vout = malloc(nout * sizeof *vout);
    double *y = malloc(nout * sizeof *y);
    if (!vout || !y) die("out of memory", NULL);
    for (size_t i = 0; i < nout; i++) vout[i] = (fmi2ValueReference)strtoul(argv[7 + i], NULL, 10);

    snprintf(path, sizeof path, "%s/binaries/linux64/%s.so", dir, model);
    void *lib = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!lib) die("dlopen failed", dlerror());
    LOAD(Instantiate); LOAD(SetupExperiment); LOAD(EnterInitializationMode);
    LOAD(ExitInitializationMode); LOAD(SetReal); LOAD(GetReal); LOAD(DoStep);
    LOAD(Terminate); LOAD(FreeInstance);

    /* The wrapper strips a literal "file://" only: the URI must be file:///abs/path. */
    snprintf(uri, sizeof uri, "file://%s/resources", dir);
    const fmi2CallbackFunctions callbacks = {logger, calloc, free, NULL, NULL};
    fmi2Component c = Instantiate(model, fmi2CoSimulation, guid, uri, &callbacks, fmi2False, fmi2True);
    if (!c) die("fmi2Instantiate failed", uri);

    /* Time follows the crank: one revolution at speed W takes 2*pi/W seconds. */
    const double h = 2.0 * M_PI / (w * n);
    CHECK(SetupExperiment(c, fmi2False, 0.0, 0.0, fmi2False, 0.0));
    CHECK(EnterInitializationMode(c)); /* parameters keep their defaults */
    CHECK(ExitInitializationMode(c));

    const fmi2ValueReference vin[4] = {0, 1, 2, 3}; /* theta, omega, alpha, load */
    const int quiet = getenv("HOST_QUIET") != NULL; /* timing only: print no outputs */
    const double t0 = seconds();
    for (int k = 0; k < n; k++) {
        const double u[4] = {2.0 * M_PI * k / n, w, 0.0, load};
        CHECK(SetReal(c, vin, 4, u));
        CHECK(DoStep(c, k * h, h, fmi2True));
        CHECK(GetReal(c, vout, nout, y));
        if (quiet) continue;
        printf("%.17g", u[0]);
        for (size_t i = 0; i < nout; i++) printf(",%.17g", y[i]);
        putchar('\n');
    }
    const double dt = seconds() - t0;
    fprintf(stderr, "%d steps in %.3f s = %.4f us/step\n", n, dt, 1e6 * dt / n);

    CHECK(Terminate(c));
    FreeInstance(c);
    dlclose(lib);
    free(vout);
    free(y);
    return 0;
}
