/* Minimal FMI 2.0 / 3.0 co-simulation host for the linkage FMUs (pythonfmu or native).
 *
 * usage: host [-3] [-d] DIR MODEL GUID N W L VR...
 *   -3     FMI 3.0 (default FMI 2.0)
 *   -d     a drive FMU (<Model>Drive): N steps over one second with tau = W and load = L
 *          (valueReferences 0 and 1), printing "time,<outputs...>"
 *   DIR    unzipped FMU folder          MODEL  model identifier
 *          (the library: DIR/binaries/<this platform>/MODEL<suffix>, host_platform.h)
 *   GUID   the guid (FMI 3.0: instantiationToken) of DIR/modelDescription.xml
 *   N      steps over one revolution    W, L   crank speed omega [rad/s] and load
 *   VR...  valueReferences of the Real (Float64) outputs to print
 * Step k sets theta = 2*pi*k/N, omega = W, alpha = 0, load = L (valueReferences 0..3),
 * does one step and prints "theta,<outputs...>" to stdout; the wall time goes to stderr.
 *
 * build: cc -std=c99 -O2 -Wall -Wextra -o host host.c -I<fmpy>/c-code -ldl
 *        (for Windows: zig cc -target x86_64-windows-gnu ..., no -ldl; see host_platform.h)
 * run:   LD_PRELOAD=<libpython.so> PYTHONPATH=<site-packages with numpy> ./host ...
 * The pythonfmu wrapper does not link libpython, so it must already be loaded globally;
 * a native FMU needs nothing.
 */
#define _XOPEN_SOURCE 700 /* realpath, clock_gettime */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2FunctionTypes.h"
#include "fmi3FunctionTypes.h"
#include "host_platform.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* Worst status the FMU has logged (fmi2Status and fmi3Status have the same values). */
static int worst_logged = fmi2OK;

/* Print the reason and stop at once, without tearing down an FMU left in an unknown state. */
static void die(const char *what, const char *detail) {
    fprintf(stderr, "%s: %s\n", what, detail ? detail : "");
    fflush(stdout);
    _Exit(1);
}

/* Stop on a status other than OK, or once an error was logged, naming the call. */
static void check(int status, const char *call) {
    if (status == fmi2OK && worst_logged < fmi2Error) return;
    fprintf(stderr, "%s returned status %d (worst logged status %d)\n", call, status,
            worst_logged);
    fflush(stdout);
    _Exit(2);
}
#define CHECK(call) check((int)(call), #call)

/* Resolve the function <prefix><name> of the library `lib` into a local `name`. */
#define LOAD(prefix, name)                                                             \
    prefix##name##TYPE *name = (prefix##name##TYPE *)library_symbol(lib, #prefix #name); \
    if (!name) die("missing symbol " #prefix #name, library_error())

/* pythonfmu passes its log text as the format string without arguments, so it is
 * printed literally: a '%' in a Python message must not reach printf. */
static void logger2(fmi2ComponentEnvironment env, fmi2String instance, fmi2Status status,
                    fmi2String category, fmi2String message, ...) {
    (void)env;
    if ((int)status > worst_logged) worst_logged = (int)status;
    fprintf(stderr, "[%s] status %d, %s: %s\n", instance, (int)status,
            category ? category : "-", message);
}

static void logger3(fmi3InstanceEnvironment env, fmi3Status status, fmi3String category,
                    fmi3String message) {
    (void)env;
    if ((int)status > worst_logged) worst_logged = (int)status;
    fprintf(stderr, "status %d, %s: %s\n", (int)status, category ? category : "-", message);
}

typedef struct {
    const char *dir, *model, *guid;
    int n, drive;
    double w, load;
    size_t nout;
    unsigned *vout;
    double *y;
} Run;

static const unsigned VIN[4] = {0, 1, 2, 3}; /* theta, omega, alpha, load; a drive's tau, load */

/* Step k's inputs (how many) and step size. */
static size_t inputs(const Run *r, int k, double u[4], double *h) {
    if (r->drive) {
        u[0] = r->w, u[1] = r->load;
        *h = 1.0 / r->n;
        return 2;
    }
    u[0] = 2.0 * M_PI * k / r->n, u[1] = r->w, u[2] = 0.0, u[3] = r->load;
    /* Time follows the crank: one revolution at speed W takes 2*pi/W seconds. */
    *h = 2.0 * M_PI / (r->w * r->n);
    return 4;
}

static void print_step(const Run *r, double theta) {
    if (getenv("HOST_QUIET")) return; /* timing only: print no outputs */
    printf("%.17g", theta);
    for (size_t i = 0; i < r->nout; i++) printf(",%.17g", r->y[i]);
    putchar('\n');
}

/* Run the FMI 2.0 FMU; the seconds its steps took. */
static double run2(const Run *r, Library lib) {
    LOAD(fmi2, Instantiate); LOAD(fmi2, SetupExperiment); LOAD(fmi2, EnterInitializationMode);
    LOAD(fmi2, ExitInitializationMode); LOAD(fmi2, SetReal); LOAD(fmi2, GetReal);
    LOAD(fmi2, DoStep); LOAD(fmi2, Terminate); LOAD(fmi2, FreeInstance);

    /* A file URI: file:///abs/path (pythonfmu's wrapper strips a literal "file://"), or
     * file:///C:/abs/path on Windows. */
    char uri[PATH_SIZE + 64];
    snprintf(uri, sizeof uri, "file://%s%s/resources", r->dir[0] == '/' ? "" : "/", r->dir);
    for (char *p = uri; *p; p++)
        if (*p == '\\') *p = '/';
    const fmi2CallbackFunctions callbacks = {logger2, calloc, free, NULL, NULL};
    fmi2Component c = Instantiate(r->model, fmi2CoSimulation, r->guid, uri, &callbacks,
                                  fmi2False, fmi2True);
    if (!c) die("fmi2Instantiate failed", uri);

    CHECK(SetupExperiment(c, fmi2False, 0.0, 0.0, fmi2False, 0.0));
    CHECK(EnterInitializationMode(c)); /* parameters keep their defaults */
    CHECK(ExitInitializationMode(c));
    const double t0 = seconds();
    for (int k = 0; k < r->n; k++) {
        double u[4], h;
        const size_t nu = inputs(r, k, u, &h);
        CHECK(SetReal(c, VIN, nu, u));
        CHECK(DoStep(c, k * h, h, fmi2True));
        CHECK(GetReal(c, r->vout, r->nout, r->y));
        print_step(r, r->drive ? (k + 1) * h : u[0]);
    }
    const double dt = seconds() - t0;
    CHECK(Terminate(c));
    FreeInstance(c);
    return dt;
}

/* Run the FMI 3.0 FMU; the seconds its steps took. */
static double run3(const Run *r, Library lib) {
    LOAD(fmi3, InstantiateCoSimulation); LOAD(fmi3, EnterInitializationMode);
    LOAD(fmi3, ExitInitializationMode); LOAD(fmi3, SetFloat64); LOAD(fmi3, GetFloat64);
    LOAD(fmi3, DoStep); LOAD(fmi3, Terminate); LOAD(fmi3, FreeInstance);

    char resources[PATH_SIZE + 64]; /* a native path, ending with a separator */
    snprintf(resources, sizeof resources, "%s/resources/", r->dir);
    fmi3Instance c = InstantiateCoSimulation(r->model, r->guid, resources, fmi3False, fmi3True,
                                             fmi3False, fmi3False, NULL, 0, NULL, logger3,
                                             NULL);
    if (!c) die("fmi3InstantiateCoSimulation failed", resources);

    CHECK(EnterInitializationMode(c, fmi3False, 0.0, 0.0, fmi3False, 0.0));
    CHECK(ExitInitializationMode(c));
    const double t0 = seconds();
    for (int k = 0; k < r->n; k++) {
        double u[4], h;
        const size_t nu = inputs(r, k, u, &h);
        fmi3Boolean event, terminate, early;
        fmi3Float64 last;
        CHECK(SetFloat64(c, VIN, nu, u, nu));
        CHECK(DoStep(c, k * h, h, fmi3True, &event, &terminate, &early, &last));
        CHECK(GetFloat64(c, r->vout, r->nout, r->y, r->nout));
        print_step(r, r->drive ? (k + 1) * h : u[0]);
    }
    const double dt = seconds() - t0;
    CHECK(Terminate(c));
    FreeInstance(c);
    return dt;
}

int main(int argc, char **argv) {
    const int fmi3 = argc > 1 && !strcmp(argv[1], "-3");
    argv += fmi3, argc -= fmi3;
    const int drive = argc > 1 && !strcmp(argv[1], "-d");
    argv += drive, argc -= drive;
    if (argc < 8) die("usage", "host [-3] [-d] DIR MODEL GUID N W L VR...");
    char dir[PATH_SIZE], path[PATH_SIZE + 256];
    if (!absolute_path(argv[1], dir)) die("no such folder", argv[1]);
    Run r = {dir, argv[2], argv[3], atoi(argv[4]), drive, atof(argv[5]), atof(argv[6]),
             (size_t)(argc - 7), NULL, NULL};
    if (r.n < 1 || !(r.w > 0)) die("N and W must be positive", NULL);
    r.vout = malloc(r.nout * sizeof *r.vout);
    r.y = malloc(r.nout * sizeof *r.y);
    if (!r.vout || !r.y) die("out of memory", NULL);
    for (size_t i = 0; i < r.nout; i++) r.vout[i] = (unsigned)strtoul(argv[7 + i], NULL, 10);

    const char *platform = fmi3 ? FMI3_PLATFORM : FMI2_PLATFORM;
    if (!platform) die("FMI 2.0 has no platform name for this machine", "use -3");
    snprintf(path, sizeof path, "%s/binaries/%s/%s" LIBRARY_SUFFIX, dir, platform, r.model);
    Library lib = library_open(path);
    if (!lib) die("cannot load the library", library_error());

    const double dt = fmi3 ? run3(&r, lib) : run2(&r, lib);
    fprintf(stderr, "%d steps in %.3f s = %.4f us/step\n", r.n, dt, 1e6 * dt / r.n);
    library_close(lib);
    free(r.vout);
    free(r.y);
    return 0;
}
