/* The continuous states of the FMI framework (framework.c includes this file when config.h
 * names continuous states: N_STATES > 0): what a model driven by its inputs, rather than
 * told its motion, adds to the framework.
 *
 * - Co-simulation: DoStep integrates the states over the step with an embedded explicit
 *   Runge-Kutta pair, Dormand and Prince's 5(4) (the 5th-order solution is taken), its
 *   error held to the `tolerance` parameter (relative and absolute, on every state) by
 *   the standard step-size controller; as many substeps as that takes, up to MAX_SUBSTEPS
 *   (past them the step ends where they reach, Discard, the reason naming the speed and
 *   the substeps the tolerance would need). The next substep
 *   is remembered between steps and kept in FMU states. A stage at which the backend
 *   cannot give the derivatives (the linkage cannot be assembled there) is a limit: the
 *   substep is halved, and the step goes on from any shorter substep that succeeds,
 *   until the limit is located to the tolerance (the states would change by less than it
 *   before the limit) or to the resolution of the time; the step then ends there:
 *   Discard, the last successful time that of the last good state, whose outputs the
 *   reads give. With friction, the crank moving one way is integrated with the friction
 *   against that way throughout (its equation continues smoothly past omega = 0, so the
 *   substeps do not shrink towards the stop), and a stop, omega reaching 0, is an event:
 *   a substep across it is shortened to it by the Illinois method on omega, to the
 *   tolerance. Wherever omega is 0 (the step's start, a stop) the friction band decides:
 *   the crank sticks for the rest of the step, or moves off the way tau leaves the band.
 * - Model exchange: the importer integrates; SetTime, SetContinuousStates,
 *   GetContinuousStates, GetDerivatives (Discard, with NaN and a log, where the backend
 *   cannot give them), the nominals (1), the event indicators (the stops and starts),
 *   the event update of the discrete state `motion` (a stop sets omega to 0, a start
 *   from rest to +-DBL_MIN), and the modes: after initialisation event mode,
 *   continuous-time mode, and back.
 *
 * The backend gives the derivatives: backend_derivatives(in, v, x, dir, dx, why, size),
 * with the inputs and parameters in `v`, the states `x` and the way `dir` the crank moves
 * (with friction: +1 or -1, the friction against it whatever the sign of omega): LK_OK;
 * LK_DISCARD with `why`.
 */
#include <float.h>

/* Dormand and Prince's 5(4) pair: nodes, the stages' coefficients (the last row is the
 * 5th-order solution's weights: first same as last), and the weights of the error
 * estimate (5th order minus 4th). */
static const double DP_A[7][6] = {
    {0},
    {1.0 / 5.0},
    {3.0 / 40.0, 9.0 / 40.0},
    {44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0},
    {19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0},
    {9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0, -5103.0 / 18656.0},
    {35.0 / 384.0, 0.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0}};
static const double DP_E[7] = {71.0 / 57600.0, 0.0, -71.0 / 16695.0, 71.0 / 1920.0,
                               -17253.0 / 339200.0, 22.0 / 525.0, -1.0 / 40.0};
/* The most substeps one DoStep takes (rejected ones too), so that its work is bounded: a
 * substep costs about 0.7 us in the four-bar, 14 to 16 us in the six-bar with friction
 * (0.7 and 16 ms a step at most). A step that needs more ends where the last of them does, with
 * Discard (its motion is real; a shorter step goes on from there): tau = 1e10 spins the
 * four-bar's crank to 2e7 rad/s in 45 us, and a step of 10 ms then needs millions. At
 * ordinary speeds the bound is far: 1000 substeps take the four-bar under tau = 2 through
 * 63 rad (ten revolutions, to 200 rad/s) at the default tolerance, 4.6 rad at 1e-14. */
#define MAX_SUBSTEPS 1000L

/* The states in force, for a message. */
static void describe_states(const double *x, char *text, size_t size) {
    size_t n = 0;
    text[0] = '\0';
    for (int k = 0; k < N_STATES && n < size; k++) {
        char value[32];
        n += (size_t)snprintf(text + n, size - n, "%s%s = %s", k ? ", " : "",
                              VARIABLES[STATES[k]].name, shortest(x[k], value, sizeof value));
    }
}

/* Why no substep the tolerance accepts is long enough for the time to resolve it, at the
 * states `x` whose derivatives are `dx` (the speed, and the acceleration that needs it). */
static void too_fine(char *why, size_t size, const double *x, const double *dx, double tol,
                     double resolution) {
    char w[32], a[32], t[32];
    snprintf(why, size, "at omega = %s rad/s and alpha = %s rad/s2 the tolerance %s needs "
             "substeps shorter than the resolution of the time (%.2g s)",
             shortest(x[1], w, sizeof w), shortest(dx[1], a, sizeof a),
             shortest(tol, t, sizeof t), resolution);
}

/* The weighted RMS norm of `e` against the tolerance at the states `a` and `b`. */
static double error_norm(const double *e, const double *a, const double *b, double tol) {
    double sum = 0.0;
    for (int k = 0; k < N_STATES; k++) {
        const double scale = tol + tol * fmax(fabs(a[k]), fabs(b[k]));
        sum += (e[k] / scale) * (e[k] / scale);
    }
    return sqrt(sum / N_STATES);
}

/* A first substep from the states and their derivatives (Hairer, Norsett and Wanner's
 * first guess, without its second evaluation), at most `h`. */
static double first_substep(const double *x, const double *dx, double tol, double h) {
    const double d0 = error_norm(x, x, x, tol), d1 = error_norm(dx, x, x, tol);
    const double guess = d0 > 1e-5 && d1 > 1e-5 ? 0.01 * d0 / d1 : 1e-6;
    return fmin(guess, h);
}

/* 1 if the states change by less than the tolerance over `span` from `x`, at the rates `dx`,
 * or `span` is below the resolution of the time `t`: a limit located. */
static int located(const double *x, const double *dx, double tol, double span, double t) {
    if (span <= 4.0 * DBL_EPSILON * fabs(t)) return 1;
    for (int k = 0; k < N_STATES; k++)
        if (span * fabs(dx[k]) > tol + tol * fabs(x[k])) return 0;
    return 1;
}

/* One Dormand-Prince substep of `step` from `x`, whose derivatives are in k[0], of the crank
 * moving `dir`: the stages k[1..6] and the 5th-order solution `y` (k[6] its derivatives). */
static Status dp_substep(Instance *in, const char *call, const double *x, int dir,
                         double k[7][N_STATES], double step, double *y, char *why,
                         size_t size) {
    Status s = LK_OK;
    for (int j = 1; j < 7 && s == LK_OK; j++) {
        for (int i = 0; i < N_STATES; i++) {
            double sum = 0.0;
            for (int m = 0; m < j; m++) sum += DP_A[j][m] * k[m][i];
            y[i] = x[i] + step * sum;
        }
        s = answer(in, call, backend_derivatives(in, &in->values, y, dir, k[j], why, size));
    }
    return s;
}

/* Where omega, positive times `dir` at `x` and not at the end of the substep `*step` (whose
 * end state is `y`), reaches 0: by the Illinois method on the substep's length, each trial a
 * substep from `x` (whose derivatives are `k0`), until omega changes by less than the
 * tolerance over the bracket or it is below the resolution of the time. `*step` and `y`
 * become the substep to the stop (omega 0 in `y`). */
static Status locate_stop(Instance *in, const char *call, const double *x, const double *k0,
                          int dir, double t, double tol, double *step, double *y, int *at_once,
                          char *why, size_t size) {
    double k[7][N_STATES], trial[N_STATES], a = 0.0, b = *step;
    double ga = dir * x[1], gb = dir * y[1];
    int side = 0;
    memcpy(k[0], k0, sizeof k[0]);
    for (int n = 0; n < 200 && gb != 0.0; n++) {
        const double rate = fmax(fabs(k0[1]), fabs(ga - gb) / (b - a));
        if ((b - a) * rate <= tol || b - a <= 4.0 * DBL_EPSILON * fabs(t + b)) break;
        double c = b - gb * (b - a) / (gb - ga);
        if (!(c > a && c < b)) c = 0.5 * (a + b);
        Status s = dp_substep(in, call, x, dir, k, c, trial, why, size);
        if (s != LK_OK) return s;
        const double gc = dir * trial[1];
        if (gc > 0.0) {
            a = c, ga = gc;
            if (side == 1) gb *= 0.5; /* Illinois: the end kept twice is halved */
            side = 1;
        } else {
            b = c, gb = gc;
            memcpy(y, trial, sizeof trial);
            if (side == -1) ga *= 0.5;
            side = -1;
        }
    }
    *step = b;
    y[1] = 0.0;
    *at_once = a == 0.0; /* no trial found omega turned `dir`-wards */
    return LK_OK;
}

/* Integrate the states `x` of the crank moving `dir` (+1, -1; 0 without friction) from
 * `t + *done` towards `t + h`, each substep within the tolerance; with friction, stop
 * where omega reaches 0 (`*stopped`, omega then exactly 0; 2 where omega never turned
 * `dir`-wards: a crank from rest that cannot move off). LK_OK at the end of the step
 * or a stop; LK_DISCARD where the motion cannot go on (`*done` and `x` those of the last
 * good substep, `why` says why); LK_ERROR for a failed backend. */
static Status integrate(Instance *in, const char *call, double t, double h, double *x,
                        double *done, int dir, int *stopped, long *substeps, char *why,
                        size_t size) {
    double y[N_STATES], e[N_STATES], k[7][N_STATES];
    const double tol = in->values.real[TOLERANCE_VR];
    *stopped = 0;
    Status s = answer(in, call, backend_derivatives(in, &in->values, x, dir, k[0], why, size));
    if (s != LK_OK) return s;
    double hs = in->substep > 0.0 ? in->substep : first_substep(x, k[0], tol, h - *done);
    double limit = INFINITY; /* a substep from `done` that reached a stage without derivatives */
    char limit_why[512] = "";
    int rejected = 0;
    while (*done < h) {
        if (++*substeps > MAX_SUBSTEPS) { /* the bound: the rest at the substep in force */
            char w[32], tl[32];
            in->substep = hs;
            snprintf(why, size, "%ld substeps, the most one step takes, end there: the crank "
                     "turns at omega = %s rad/s, and the tolerance %s needs about %.2g "
                     "substeps for the whole step (steps of about %.2g s fit)", MAX_SUBSTEPS,
                     shortest(x[1], w, sizeof w), shortest(tol, tl, sizeof tl),
                     MAX_SUBSTEPS + (h - *done) / hs, *done);
            return LK_DISCARD;
        }
        const double left = h - *done;
        double step = hs;
        int last = 0;
        if (step >= left) step = left, last = 1;
        if (step >= limit) step = 0.5 * limit, last = 0;
        s = dp_substep(in, call, x, dir, k, step, y, why, size);
        if (s > LK_DISCARD) return s;
        if (s == LK_DISCARD) { /* past a limit: bisect towards it */
            limit = step;
            set_text(limit_why, sizeof limit_why, why);
            if (located(x, k[0], tol, limit, fmax(fabs(t + *done), fabs(t + h)))) break;
            hs = 0.5 * step;
            continue;
        }
        for (int i = 0; i < N_STATES; i++) {
            double sum = 0.0;
            for (int m = 0; m < 7; m++) sum += DP_E[m] * k[m][i];
            e[i] = step * sum;
        }
        const double err = error_norm(e, x, y, tol);
        /* a substep the time cannot resolve: at most that of the step's end (at t = 0,
         * a substep below the step's own resolution is as meaningless) */
        const double resolution = 4.0 * DBL_EPSILON * fmax(fabs(t + *done), fabs(t + h));
        if (!(err <= 1.0)) { /* rejected (a NaN estimate too): shorter */
            hs = step * (err == err ? fmax(0.2, 0.9 * pow(err, -0.2)) : 0.2);
            rejected = 1;
            if (hs <= resolution) {
                too_fine(why, size, x, k[0], tol, resolution);
                return LK_DISCARD;
            }
            continue;
        }
        if (dir && dir * y[1] <= 0.0) { /* the crank stops within the substep */
            const double whole = step;
            int at_once;
            s = locate_stop(in, call, x, k[0], dir, t + *done, tol, &step, y, &at_once, why,
                            size);
            if (s != LK_OK) return s;
            if (at_once && x[1] == 0.0) { /* from rest, not even the start moves off */
                *stopped = 2;
                in->substep = hs;
                return LK_OK;
            }
            *done = last && step == whole ? h : *done + step;
            memcpy(x, y, sizeof y);
            *stopped = 1;
            in->substep = hs;
            return LK_OK;
        }
        if (!last && step <= resolution) {
            too_fine(why, size, x, k[0], tol, resolution);
            return LK_DISCARD;
        }
        *done = last ? h : *done + step;
        limit -= step;
        memcpy(x, y, sizeof y);
        memcpy(k[0], k[6], sizeof k[0]);
        double grow = err > 0.0 ? 0.9 * pow(err, -0.2) : 5.0;
        grow = fmin(rejected ? 1.0 : 5.0, fmax(0.2, grow));
        rejected = 0;
        /* a last substep cut to the end of the step does not shrink the next one */
        hs = last ? fmax(step * grow, hs) : step * grow;
        if (limit < INFINITY && located(x, k[0], tol, limit, fmax(fabs(t + *done), fabs(t + h))))
            break;
    }
    in->substep = hs;
    if (*done >= h) return LK_OK;
    set_text(why, size, limit_why);
    return LK_DISCARD;
}

/* The most stops and starts in one step: a guard, never reached by a motion that goes on */
#define MAX_SWITCHES 100000L

/* Integrate the states from `t` over `h` (DoStep of a model with continuous states):
 * LK_OK at `t + h`; LK_DISCARD where the motion cannot go on (at its start: nothing
 * changes; later: the states and time of the last good substep); LK_ERROR for an invalid
 * parameter set or a failed backend. With friction, wherever omega is 0 (the step's start,
 * a stop located inside it) the friction band decides: the crank sticks for the rest of
 * the step (tau is held over it), or moves off the way tau leaves the band. */
static Status advance(Instance *in, const char *call, double t, double h) {
    char why[512], at[32], states[256];
    if (prepare(in, call) != LK_OK) {
        if (in->machine != S_FAILED)
            say(in, LK_ERROR, "%s: the parameter set is invalid: %s", call, in->problem);
        return LK_ERROR;
    }
    double x[N_STATES];
    for (int i = 0; i < N_STATES; i++) x[i] = in->values.real[STATES[i]];
    const int live = friction_live((const Model *)in->model);
    double done = 0.0;
    long substeps = 0, switches = 0;
    Status s = LK_DISCARD;
    why[0] = '\0';
    if (!unfit_inputs(in, why, sizeof why)[0]) {
        s = LK_OK;
        while (done < h && s == LK_OK) {
            int dir = 0, stopped = 0, has_band;
            double lo, hi;
            if (live) {
                s = answer(in, call, motion_of(in, &in->values, x, &dir, &lo, &hi, &has_band,
                                               why, sizeof why));
                if (s != LK_OK) break;
                in->values.integer[MOTION_VR] = dir;
                if (!dir) { /* stuck in the band: theta and omega stay, over the rest */
                    done = h;
                    break;
                }
            }
            s = integrate(in, call, t, h, x, &done, dir, &stopped, &substeps, why, sizeof why);
            if (s == LK_OK && stopped == 2) {
                /* the band lets it go, but its acceleration turns back at once (friction
                 * all but locks it): it cannot move off, and stays for the rest */
                in->values.integer[MOTION_VR] = 0;
                done = h;
                break;
            }
            if (s == LK_OK && stopped && ++switches > MAX_SWITCHES) {
                snprintf(why, sizeof why, "the crank stops and starts more than %ld times in "
                         "one step", MAX_SWITCHES);
                s = LK_DISCARD;
            }
        }
        if (s == LK_OK && live && x[1] == 0.0 && in->values.integer[MOTION_VR]) {
            /* stopped at the step's end: the band says */
            int dir, has_band;
            double lo, hi;
            s = answer(in, call, motion_of(in, &in->values, x, &dir, &lo, &hi, &has_band, why,
                                           sizeof why));
            if (s == LK_OK) in->values.integer[MOTION_VR] = dir;
        }
    }
    if (s > LK_DISCARD) return say(in, LK_ERROR, "%s: %s", call, why[0] ? why : "the backend failed");
    if (s == LK_DISCARD && done == 0.0) { /* not even the start: the states stay */
        in->discarded = 1;
        for (int i = 0; i < N_STATES; i++) x[i] = in->values.real[STATES[i]];
        describe_states(x, states, sizeof states);
        return say(in, LK_DISCARD, "%s: the motion cannot start at t = %s from %s: %s", call,
                   shortest(t, at, sizeof at), states, why);
    }
    for (int i = 0; i < N_STATES; i++) in->values.real[STATES[i]] = x[i];
    if (live && x[1] != 0.0) in->values.integer[MOTION_VR] = x[1] > 0.0 ? 1 : -1;
    in->time = t + done;
    changed(in, 0);
    in->discarded = done < h;
    if (done >= h) return LK_OK;
    describe_states(x, states, sizeof states);
    char end[32];
    if (substeps > MAX_SUBSTEPS) /* the motion goes on: this step took all it may */
        return say(in, LK_DISCARD, "%s: the step from t = %s ends at t = %s (%s; "
                   "lastSuccessfulTime), with the outputs of that state: %s", call,
                   shortest(t, at, sizeof at), shortest(t + done, end, sizeof end), states, why);
    return say(in, LK_DISCARD, "%s: the motion cannot go on past t = %s (%s): %s; the step "
               "from t = %s ends there (lastSuccessfulTime), with the outputs of that state",
               call, shortest(t + done, end, sizeof end), states, why,
               shortest(t, at, sizeof at));
}

/* -- model exchange ------------------------------------------------------------------- */
/* `n` values at `values` for the continuous states: Error unless it is N_STATES of them. */
static Status check_states(const Instance *in, const char *call, const void *values, size_t n,
                           const char *what) {
    if (n != N_STATES)
        return say(in, LK_ERROR, "%s: %s = %zu, but " MODEL_IDENTIFIER " has %d continuous "
                   "states", call, what, n, N_STATES);
    if (!values) return say(in, LK_ERROR, "%s: the array is NULL", call);
    return LK_OK;
}

static Status lk_set_time(void *c, const char *call, double time) {
    INSTANCE(c, call);
    if (require(in, call, IN(S_EVENT) | IN(S_CONTINUOUS))) return LK_ERROR;
    if (!isfinite(time)) return say(in, LK_ERROR, "%s: time = %g is not finite", call, time);
    in->time = time; /* the model is autonomous: nothing else changes */
    return LK_OK;
}

static Status lk_set_continuous_states(void *c, const char *call, const double x[], size_t n) {
    INSTANCE(c, call);
    if (require(in, call, IN(S_CONTINUOUS)) || check_states(in, call, x, n, "nContinuousStates"))
        return LK_ERROR;
    for (int k = 0; k < N_STATES; k++) /* check all before setting any */
        if (!isfinite(x[k]))
            return say(in, LK_ERROR, "%s: the continuous state %s = %g is not a finite number",
                       call, VARIABLES[STATES[k]].name, x[k]);
    for (int k = 0; k < N_STATES; k++) {
        if (in->values.real[STATES[k]] != x[k]) changed(in, 0);
        in->values.real[STATES[k]] = x[k];
    }
    return LK_OK;
}

static Status lk_get_continuous_states(void *c, const char *call, double x[], size_t n) {
    INSTANCE(c, call);
    if (require(in, call, READABLE) || check_states(in, call, x, n, "nContinuousStates"))
        return LK_ERROR;
    start_states(in);
    Status status = LK_OK;
    for (int k = 0; k < N_STATES; k++) {
        x[k] = in->values.real[STATES[k]];
        const Status s = read_state(in, call, k, x[k]);
        if (s > status) status = s;
    }
    return status;
}

/* The derivatives of the states: Discard (NaN, with a log) where they cannot be had. */
static Status lk_get_derivatives(void *c, const char *call, double dx[], size_t n) {
    INSTANCE(c, call);
    if (require(in, call, READABLE) || check_states(in, call, dx, n, "nContinuousStates"))
        return LK_ERROR;
    Status s = evaluate(in, call);
    if (s == LK_ERROR) {
        if (in->machine != S_FAILED && !in->prepared)
            say(in, LK_ERROR, "%s: the parameter set is invalid: %s", call, in->problem);
        return LK_ERROR;
    }
    for (int k = 0; k < N_STATES; k++) dx[k] = in->outputs[DERIVATIVES[k]];
    if (s == LK_DISCARD) report(in, LK_DISCARD, call, in->time);
    return s;
}

static Status lk_get_nominals(void *c, const char *call, double nominals[], size_t n) {
    INSTANCE(c, call);
    if (require(in, call, READABLE | IN(S_INSTANTIATED)) ||
        check_states(in, call, nominals, n, "nContinuousStates"))
        return LK_ERROR;
    for (int k = 0; k < N_STATES; k++) nominals[k] = 1.0;
    return LK_OK;
}

/* The event indicators (EVENTS among the outputs): Discard (NaN, with a log) where they
 * cannot be had, as the derivatives. */
static Status lk_get_event_indicators(void *c, const char *call, double z[], size_t n) {
    INSTANCE(c, call);
    if (require(in, call, READABLE)) return LK_ERROR;
    if (n != N_EVENTS)
        return say(in, LK_ERROR, "%s: nEventIndicators = %zu, but " MODEL_IDENTIFIER " has %d",
                   call, n, N_EVENTS);
    if (n && !z) return say(in, LK_ERROR, "%s: the array is NULL", call);
    Status s = evaluate(in, call);
    if (s == LK_ERROR) {
        if (in->machine != S_FAILED && !in->prepared)
            say(in, LK_ERROR, "%s: the parameter set is invalid: %s", call, in->problem);
        return LK_ERROR;
    }
    for (int k = 0; k < N_EVENTS; k++) z[k] = in->outputs[EVENTS[k]];
    if (s == LK_DISCARD) report(in, LK_DISCARD, call, in->time);
    return s;
}

/* Model exchange's event update (an event indicator crossed 0, an input changed, the
 * initial one): with friction, a crank that moved `motion` and whose omega reached or
 * crossed 0 stops there (omega set to 0), and at rest the friction band decides `motion`
 * (0: it sticks, else the way tau leaves the band, its acceleration that way); a moving
 * crank keeps moving the way omega turns. A crank that leaves rest the way `dir` gets
 * omega = dir DBL_MIN (a speed no output shows): the indicator of its motion is then > 0
 * from the start, and an importer that restarts its integrator only where the states
 * change (valuesOfContinuousStatesChanged, `*moved`) restarts it at every start as at
 * every stop, its history of the crank at rest left behind. */
static Status drive_event(Instance *in, const char *call, int *moved) {
    char why[512];
    *moved = 0;
    if (prepare(in, call) != LK_OK) {
        if (in->machine != S_FAILED)
            say(in, LK_ERROR, "%s: the parameter set is invalid: %s", call, in->problem);
        return LK_ERROR;
    }
    double x[N_STATES];
    for (int k = 0; k < N_STATES; k++) x[k] = in->values.real[STATES[k]];
    int *motion = &in->values.integer[MOTION_VR];
    const int was = *motion;
    if (!friction_live((const Model *)in->model)) {
        *motion = (x[1] > 0.0) - (x[1] < 0.0);
    }
#if DRIVE_FRICTION
    else if (x[1] != 0.0 && was * x[1] > 0.0) {
        /* moving on */
    } else if (x[1] != 0.0 && !was) { /* set moving while it stuck: it moves as omega says */
        *motion = x[1] > 0.0 ? 1 : -1;
    } else {
        if (x[1] != 0.0) { /* omega crossed 0 as the crank moved `was`: it stops there */
            x[1] = 0.0;
            in->values.real[STATES[1]] = 0.0;
            *moved = 1;
        }
        double lo, hi;
        char at[32];
        Status s = LK_DISCARD;
        why[0] = '\0';
        if (!unfit_inputs(in, why, sizeof why)[0])
            s = answer(in, call, friction_band((const Model *)in->model, &in->values, x[0], &lo,
                                               &hi, why, sizeof why));
        if (s > LK_DISCARD) return say(in, LK_ERROR, "%s: %s", call, why);
        if (s == LK_DISCARD) {
            changed(in, 0);
            return say(in, LK_DISCARD, "%s: at rest at t = %s, the friction band cannot be had: "
                       "%s", call, shortest(in->time, at, sizeof at), why);
        }
        *motion = breakaway(&in->values, lo, hi);
        if (*motion) { /* it moves off: see above */
            in->values.real[STATES[1]] = *motion * DBL_MIN;
            *moved = 1;
        }
    }
#else
    (void)why;
#endif
    if (*moved || *motion != was) changed(in, 0);
    return LK_OK;
}

static Status lk_enter_continuous_time_mode(void *c, const char *call) {
    INSTANCE(c, call);
    if (!in->exchange) return say(in, LK_ERROR, "%s: the instance is for co-simulation", call);
    return move(in, call, IN(S_EVENT), S_CONTINUOUS);
}

/* Model exchange's event mode, entered from continuous-time mode: nothing changes but the
 * mode (the event update does the work). */
static Status lk_exchange_event_mode(void *c, const char *call) {
    INSTANCE(c, call);
    return move(in, call, IN(S_CONTINUOUS), S_EVENT);
}

/* Nothing happens at the end of an integrator step: no event, no end. */
static Status lk_completed_integrator_step(void *c, const char *call) {
    INSTANCE(c, call);
    return require(in, call, IN(S_CONTINUOUS));
}
