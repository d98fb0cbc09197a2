/* The FMI framework of linkage_fmu's FMUs: what FMI 2.0 and 3.0 share, in neutral types
 * (framework.h). Included, after config.h, by the adapter of one standard (fmi2.c or
 * fmi3.c), which converts its types and names its calls; this file includes the backend
 * named by config.h's BACKEND. It owns:
 *
 * - the state machine (Instantiated -> InitializationMode -> StepMode -> Terminated; an
 *   FMI 3.0 instance whose importer uses event mode enters EventMode from
 *   InitializationMode and moves between it and StepMode as asked: there are no events);
 * - the checks of every argument before any state changes (value references, types,
 *   variables that may not be set now, booleans, UTF-8, step sizes, times): a bad call is
 *   Error with a log naming the call, the reference and the reason, nothing changed;
 * - the values of every variable, so that a value read is the value set, whatever a
 *   backend does;
 * - the parameter rules (finite, > 0, >= 0, bounds, the allowed values of integers and
 *   strings), checked with the backend's own rules at ExitInitializationMode: an invalid
 *   set is Error and the instance stays in initialisation mode, to be fixed;
 * - the dirty flag and the status policy, the same for every backend and both standards:
 *   the outputs are computed once per change of the inputs, when a step or a read needs
 *   them; inputs that cannot be solved make DoStep answer Discard (the step is not taken:
 *   the last successful time stays at its start, and the next valid step goes on) and
 *   every output read NaN with a Warning; one log per change of the inputs names the
 *   inputs, the time of the step's start and the reason (the same words from every
 *   backend);
 * - FMU states: a snapshot of every value, the time and the mode, restored whole (a state
 *   restored in step mode can be stepped at once); a state pointer that is not one of the
 *   instance's live states is an Error; serialized states are framed (model, GUID,
 *   format, length, CRC-32) and every field is checked against this model before any of
 *   it is taken;
 * - Fatal never reaches the host: a backend that reports it fails the instance, which
 *   answers Error from then on.
 *
 * The adapter sets an instance's `emit` (how to call the host's logger) and memory
 * functions, and names each call (its standard's function name) for the logs.
 */
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "framework.h"

#define LK_PATH 4096 /* the longest path of a resources folder taken */

/* S_CONTINUOUS: model exchange's continuous-time mode (a model with continuous states) */
typedef enum { S_INSTANTIATED, S_INIT, S_STEP, S_TERMINATED, S_EVENT, S_FAILED,
               S_CONTINUOUS } Machine;
/* the standard's names of the states (the adapter names the state of steps) */
static const char *const MACHINE_NAMES[] = {"Instantiated", "InitializationMode", STEP_MODE_NAME,
                                            "Terminated", "EventMode", "failed",
                                            "ContinuousTimeMode"};
#define IN(s) (1u << (s))
#define READABLE (IN(S_INIT) | IN(S_STEP) | IN(S_EVENT) | IN(S_TERMINATED) | IN(S_CONTINUOUS))
#define WRITABLE (IN(S_INSTANTIATED) | IN(S_INIT) | IN(S_STEP) | IN(S_EVENT) | IN(S_CONTINUOUS))
/* past initialisation: the parameter set was taken */
#define INITIALIZED (IN(S_STEP) | IN(S_EVENT) | IN(S_TERMINATED) | IN(S_CONTINUOUS))

/* config.h of a model with continuous states defines N_STATES, STATES (their value
 * references), STATE_STARTS (their start parameters), DERIVATIVES (their derivatives'
 * positions among the outputs) and TOLERANCE_VR (the integrator's tolerance) */
#ifndef N_STATES
#define N_STATES 0
#endif

static const char *const LOG_CATEGORIES[] = {"logStatusWarning", "logStatusDiscard",
                                             "logStatusError", "logStatusFatal", "logAll"};
#define N_CATEGORIES (sizeof LOG_CATEGORIES / sizeof *LOG_CATEGORIES)
/* the standard's names of the types (the adapter names them) */
static const char *const TYPE_NAMES[] = {TYPE_NAME_REAL, TYPE_NAME_INTEGER, "Boolean", "String"};

/* The values of every variable, by value reference (one entry per reference). */
typedef struct {
    double real[N_VARIABLES];
    int integer[N_VARIABLES];
    char *string[N_VARIABLES]; /* owned copies */
} Values;

struct Instance;
typedef void (*Emit)(const struct Instance *in, Status status, const char *category,
                     const char *message);

typedef struct Saved Saved;

typedef struct Instance {
    char *name;
    void *(*allocate)(size_t, size_t);
    void (*release)(void *);
    Emit emit;     /* the adapter's call of the host's logger */
    void *host[8]; /* what the adapter keeps of the host (its callbacks) */
    Machine machine;
    int logging;
    int event_mode_used; /* FMI 3.0: the importer enters event mode (ours has no events) */
    int exchange;        /* instantiated for model exchange (a model with continuous states) */
    double substep;      /* the integrator's next substep (0: not known yet) */
    unsigned categories; /* bit i: LOG_CATEGORIES[i] enabled; 0 = all */
    double time;         /* the last successful communication point */
    int discarded;       /* the last step was discarded */
    Values values;
    int prepared;              /* the backend took the parameters in `values` */
    char problem[512];         /* why it did not ('' = not tried since they changed) */
    int parameters_reported;   /* the problem was logged for reads */
    int fresh;                 /* `outputs` hold the outputs of the inputs in `values` */
    int solved;                /* ... and the inputs could be solved */
    int reported;              /* the unsolvable inputs were logged */
    char why[512];             /* why they could not */
    double outputs[N_OUTPUTS + 1];
    Saved *states;             /* the live FMU states of this instance */
    void *model;               /* the backend's */
} Instance;

struct Saved {
    char magic[8];
    Instance *owner;
    Saved *next;
    Machine machine;
    double time;
    double substep;
    Values values;
};

static const char STATE_MAGIC[8] = {'L', 'K', 'F', 'M', 'U', 'S', 'T', '\0'};
#define STATE_FORMAT (N_STATES ? 3u : 2u) /* 3: with the integrator's substep */

/* -- logging ------------------------------------------------------------------------ */
static int category_enabled(const Instance *in, Status status, const char *category) {
    if (status >= LK_ERROR) return 1; /* errors are always reported */
    if (!in->logging) return 0;
    if (!in->categories) return 1;
    for (unsigned i = 0; i < N_CATEGORIES; i++)
        if ((in->categories >> i & 1u) &&
            (!strcmp(LOG_CATEGORIES[i], "logAll") ||
             (category && !strcmp(category, LOG_CATEGORIES[i]))))
            return 1;
    return 0;
}

static const char *status_category(Status status) {
    return status >= LK_ERROR ? "logStatusError"
           : status == LK_DISCARD ? "logStatusDiscard"
                                  : "logStatusWarning";
}

/* Log a message (printf-style) with `status`, and return `status`. */
static Status say(const Instance *in, Status status, const char *fmt, ...) {
    char text[2048];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    const char *category = status_category(status);
    if (in->emit && category_enabled(in, status, category)) in->emit(in, status, category, text);
    return status;
}

/* `from` into `to` (`size` bytes), cut if it is longer. */
static void set_text(char *to, size_t size, const char *from) {
    size_t n = strlen(from);
    if (n >= size) n = size - 1;
    memcpy(to, from, n);
    to[n] = '\0';
}

/* `x` as Python's repr writes it: the fewest digits that read back as `x`, in scientific
 * notation below 1e-4 and from 1e16 on, else with a decimal point. */
static const char *shortest(double x, char *text, size_t size) {
    if (!isfinite(x)) {
        set_text(text, size, x != x ? "nan" : x > 0 ? "inf" : "-inf");
        return text;
    }
    int digits = 1;
    for (; digits < 17; digits++) {
        snprintf(text, size, "%.*e", digits - 1, x);
        if (strtod(text, NULL) == x) break;
    }
    snprintf(text, size, "%.*e", digits - 1, x);
    const int exponent = atoi(strchr(text, 'e') + 1);
    if (exponent < -4 || exponent >= 16) return text;
    const int decimals = digits - 1 - exponent;
    snprintf(text, size, "%.*f%s", decimals > 0 ? decimals : 0, x, decimals > 0 ? "" : ".0");
    return text;
}

/* -- checks that know no FMI type ---------------------------------------------------- */
/* 1 if `s` is well-formed UTF-8. */
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

static Status require(const Instance *in, const char *call, unsigned allowed) {
    if (allowed >> in->machine & 1u) return LK_OK;
    return say(in, LK_ERROR, "%s is not allowed in state %s", call, MACHINE_NAMES[in->machine]);
}

/* Entry `i` of a call's value references, `vr`: a variable of `type`, or Error. */
static Status check_ref(const Instance *in, const char *call, ValueReference vr, size_t i,
                        int type, const char *type_name) {
    if (vr >= N_VARIABLES || !VARIABLES[vr].name)
        return say(in, LK_ERROR, "%s: value reference %u (entry %zu) is not a variable of "
                   MODEL_IDENTIFIER, call, (unsigned)vr, i);
    if (VARIABLES[vr].type != type)
        return say(in, LK_ERROR, "%s: value reference %u ('%s') is a %s, not a %s", call,
                   (unsigned)vr, VARIABLES[vr].name, TYPE_NAMES[VARIABLES[vr].type], type_name);
    return LK_OK;
}

/* Each reference is checked before the next is read: the count is the caller's word, and
 * a count past its array ends at the first entry that is not a variable of `type`. */
static Status check_refs(const Instance *in, const char *call, const ValueReference vr[],
                         size_t nvr, const void *values, int type, const char *type_name) {
    if (nvr == 0) return LK_OK;
    if (!vr || !values)
        return say(in, LK_ERROR, "%s: %s is NULL with %zu value references", call,
                   !vr ? "the value reference array" : "the value array", nvr);
    for (size_t i = 0; i < nvr; i++)
        if (check_ref(in, call, vr[i], i, type, type_name)) return LK_ERROR;
    return LK_OK;
}

static Status check_settable(const Instance *in, const char *call, const ValueReference vr[],
                             size_t nvr, const char *exit_call) {
    for (size_t i = 0; i < nvr; i++) {
        const Variable *v = &VARIABLES[vr[i]];
        if (v->kind == K_INPUT || (v->kind == K_TUNABLE && in->machine != S_CONTINUOUS))
            continue;
        if (v->kind == K_TUNABLE)
            return say(in, LK_ERROR, "%s: '%s' (value reference %u) is a tunable parameter: "
                       "model exchange sets it in event mode, not in continuous-time mode",
                       call, v->name, (unsigned)vr[i]);
        if (v->kind == K_FIXED && (in->machine == S_INSTANTIATED || in->machine == S_INIT))
            continue;
        if (v->kind == K_STATE)
            return say(in, LK_ERROR, "%s: '%s' (value reference %u) is a continuous state: it "
                       "starts at its start parameter, and model exchange sets it with "
                       "SetContinuousStates", call, v->name, (unsigned)vr[i]);
        if (v->kind == K_DISCRETE)
            return say(in, LK_ERROR, "%s: '%s' (value reference %u) is a discrete state: the "
                       "model changes it at its events, it cannot be set", call, v->name,
                       (unsigned)vr[i]);
        return say(in, LK_ERROR, "%s: '%s' (value reference %u) %s%s", call, v->name,
                   (unsigned)vr[i],
                   v->kind == K_FIXED ? "is a fixed parameter: it can only be set before "
                                      : "is an output: it cannot be set",
                   v->kind == K_FIXED ? exit_call : "");
    }
    return LK_OK;
}

/* A value's fitness for a variable: '' if fine, else why not (into `why`). */
static const char *unfit_integer(const Variable *v, int value, char *why, size_t size) {
    why[0] = '\0';
    if (!v->allowed) return why;
    for (int k = 0; k < v->n_allowed; k++)
        if (v->allowed[k] == value) return why;
    snprintf(why, size, "%s must be %s (%s), got %d", v->name, v->rule_text, v->meaning, value);
    return why;
}

static const char *unfit_string(const Variable *v, const char *value, char *why, size_t size) {
    why[0] = '\0';
    if (!value) snprintf(why, size, "the value for '%s' is NULL", v->name);
    else if (!utf8((const unsigned char *)value))
        snprintf(why, size, "the value for '%s' is not valid UTF-8", v->name);
    else if (v->options) {
        for (int k = 0; v->options[k]; k++)
            if (!strcmp(v->options[k], value)) return why;
        snprintf(why, size, "%s must be %s, got '%s'", v->name, v->rule_text, value);
    }
    return why;
}

/* The rule of a real parameter: '' if `value` meets it. */
static const char *unfit_real(const Variable *v, double value, char *why, size_t size) {
    char a[32], b[32];
    why[0] = '\0';
    if (v->kind != K_FIXED && v->kind != K_TUNABLE) return why;
    if (!isfinite(value))
        snprintf(why, size, "%s must be a finite number, got %s", v->name,
                 shortest(value, a, sizeof a));
    else if (v->rule == RULE_POSITIVE && !(value > 0.0))
        snprintf(why, size, "%s must be > 0 (%s), got %s", v->name, v->meaning,
                 shortest(value, a, sizeof a));
    else if (v->rule == RULE_NONNEGATIVE && !(value >= 0.0))
        snprintf(why, size, "%s must be >= 0 (%s), got %s", v->name, v->meaning,
                 shortest(value, a, sizeof a));
    else if (v->rule == RULE_SIGN && !(value == 1.0 || value == -1.0))
        snprintf(why, size, "%s must be +1 or -1 (%s), got %s", v->name, v->meaning,
                 shortest(value, a, sizeof a));
    else if (value < v->min)
        snprintf(why, size, "%s must be >= %s (%s), got %s", v->name, shortest(v->min, b, sizeof b),
                 v->meaning, shortest(value, a, sizeof a));
    else if (value > v->max)
        snprintf(why, size, "%s must be <= %s (%s), got %s", v->name, shortest(v->max, b, sizeof b),
                 v->meaning, shortest(value, a, sizeof a));
    return why;
}

/* The first parameter of `values` that breaks its rule: '' if none. */
static const char *unfit_parameters(const Values *values, char *why, size_t size) {
    why[0] = '\0';
    for (unsigned vr = 0; vr < N_VARIABLES && !why[0]; vr++) {
        const Variable *v = &VARIABLES[vr];
        if (!v->name || (v->kind != K_FIXED && v->kind != K_TUNABLE)) continue;
        if (v->type == T_REAL) unfit_real(v, values->real[vr], why, size);
        else if (v->type == T_INTEGER) unfit_integer(v, values->integer[vr], why, size);
        else if (v->type == T_STRING) unfit_string(v, values->string[vr], why, size);
    }
    return why;
}

static int hex(int c) {
    return c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10
           : c >= 'A' && c <= 'F' ? c - 'A' + 10 : -1;
}

/* The absolute path of a file URI (file:///p, file:/p or file://localhost/p, each %XX
 * decoded) into `path`; 0 if `uri` is not one. */
static int file_path(const char *uri, char *path, size_t size) {
    const char *p;
    if (!strncmp(uri, "file:///", 8)) p = uri + 7;
    else if (!strncmp(uri, "file://localhost/", 17)) p = uri + 16;
    else if (!strncmp(uri, "file:/", 6) && uri[6] != '/') p = uri + 5;
    else return 0;
    size_t n = 0;
    for (; *p; p++) {
        unsigned c = (unsigned char)*p;
        if (c == '?' || c == '#') return 0;
        if (c == '%') {
            const int hi = hex(p[1]), lo = hi < 0 ? -1 : hex(p[2]);
            if (lo < 0 || !(hi | lo)) return 0;
            c = (unsigned)(hi << 4 | lo);
            p += 2;
        }
        if (n + 1 >= size) return 0;
        path[n++] = (char)c;
    }
    path[n] = '\0';
#ifdef _WIN32
    if (n > 2 && path[0] == '/' && path[2] == ':') memmove(path, path + 1, n); /* /C:/... */
#endif
    return n > 0;
}

static int absolute(const char *path) {
#ifdef _WIN32
    return (path[0] && path[1] == ':' && (path[2] == '/' || path[2] == '\\')) ||
           (path[0] == '\\' && path[1] == '\\');
#else
    return path[0] == '/';
#endif
}

/* -- values --------------------------------------------------------------------------- */
static char *copy_text(const Instance *in, const char *text) {
    char *copy = (char *)in->allocate(strlen(text) + 1, 1);
    if (copy) strcpy(copy, text);
    return copy;
}

static void release_values(const Instance *in, Values *v) {
    for (unsigned vr = 0; vr < N_VARIABLES; vr++) {
        if (v->string[vr]) in->release(v->string[vr]);
        v->string[vr] = NULL;
    }
}

/* `to` = `from`, the strings copied; 0 (and `to` unchanged) without memory. */
static int copy_values(const Instance *in, Values *to, const Values *from) {
    Values copy = *from;
    for (unsigned vr = 0; vr < N_VARIABLES; vr++) {
        if (!from->string[vr]) continue;
        if (!(copy.string[vr] = copy_text(in, from->string[vr]))) {
            for (unsigned k = 0; k < vr; k++)
                if (copy.string[k] && from->string[k]) in->release(copy.string[k]);
            return 0;
        }
    }
    release_values(in, to);
    *to = copy;
    return 1;
}

static int start_values(const Instance *in, Values *v) {
    Values start;
    memset(&start, 0, sizeof start);
    for (unsigned vr = 0; vr < N_VARIABLES; vr++) {
        const Variable *var = &VARIABLES[vr];
        if (!var->name) continue;
        start.real[vr] = var->start;
        start.integer[vr] = var->integer_start;
        start.string[vr] = (char *)var->string_start;
    }
    return copy_values(in, v, &start);
}

/* Forget what was computed from the values; `parameters`: the parameters changed too. */
static void changed(Instance *in, int parameters) {
    in->fresh = 0;
    if (parameters) {
        in->prepared = 0;
        in->problem[0] = '\0';
        in->parameters_reported = 0;
    }
}

/* -- the backend: BACKEND defines these (static: one translation unit) ------------------
 * backend_ready      once per instantiation: can this process run the backend?
 * backend_instantiate the backend's data of an instance, given the resources folder as
 *                    an absolute path (NULL if the host gave none, no file URI of one, or
 *                    a relative path: `location` is what it gave);
 *                    NULL, with a log, if it cannot
 * backend_free       ... released
 * backend_prepare    take the parameters in `v`: LK_OK, or LK_ERROR with `why`
 * backend_evaluate   the outputs (in OUTPUTS order) of the inputs in `v`, after a prepare
 *                    of its parameters: LK_OK; LK_DISCARD with `why` (no numbers) if they
 *                    cannot be solved; LK_ERROR or LK_FATAL with `why` if the call failed */
static int backend_ready(char *why, size_t size);
static void *backend_instantiate(Instance *in, const char *resources, const char *location);
static void backend_free(Instance *in);
static Status backend_prepare(Instance *in, const Values *v, char *why, size_t size);
static Status backend_evaluate(Instance *in, const Values *v, double *y, char *why, size_t size);
/* backend_tangent    (where the backend defines BACKEND_TANGENT 1) the outputs `y` and
 *                    their derivatives `dy` along the direction `dx` of the inputs (in
 *                    INPUTS order), as backend_evaluate */

#include BACKEND
#ifndef BACKEND_TANGENT
#define BACKEND_TANGENT 0
#endif

#if N_STATES > 0
static Status advance(Instance *in, const char *call, double t, double h);
static Status drive_event(Instance *in, const char *call, int *moved);
#endif

/* A backend's Fatal fails the instance for good. */
static Status answer(Instance *in, const char *call, Status status) {
    if (status == LK_FATAL) {
        in->machine = S_FAILED;
        return say(in, LK_ERROR, "%s failed fatally; this instance can only be freed", call);
    }
    return status;
}

/* -- the parameters and the outputs ----------------------------------------------------- */
/* Check the parameters with the framework's rules and the backend's; `problem` says why. */
static Status prepare(Instance *in, const char *call) {
    if (in->prepared) return LK_OK;
    if (in->problem[0]) return LK_ERROR; /* tried, and not changed since */
    if (!unfit_parameters(&in->values, in->problem, sizeof in->problem)[0]) {
        Status s = answer(in, call, backend_prepare(in, &in->values, in->problem,
                                                    sizeof in->problem));
        if (s > LK_WARNING && !in->problem[0]) strcpy(in->problem, "the backend refused it");
        if (s > LK_WARNING) return LK_ERROR;
    }
    if (in->problem[0]) return LK_ERROR;
    in->prepared = 1;
    return LK_OK;
}

/* The inputs in force, for a message. */
static void describe_inputs(const Instance *in, char *text, size_t size) {
    size_t n = 0;
    text[0] = '\0';
    for (int k = 0; k < N_INPUTS && n < size; k++) {
        char value[32];
        const unsigned vr = INPUTS[k];
        n += (size_t)snprintf(text + n, size - n, "%s%s = %s", k ? ", " : "", VARIABLES[vr].name,
                              shortest(in->values.real[vr], value, sizeof value));
    }
}

/* Why the inputs cannot be taken ('' if they can): one is not finite. */
static const char *unfit_inputs(const Instance *in, char *why, size_t size) {
    why[0] = '\0';
    for (int k = 0; k < N_INPUTS && !why[0]; k++) {
        const double x = in->values.real[INPUTS[k]];
        char value[32];
        if (!isfinite(x))
            snprintf(why, size, "input %s = %s is not a finite number", VARIABLES[INPUTS[k]].name,
                     shortest(x, value, sizeof value));
    }
    return why;
}

/* Until initialisation ends, each continuous state is its start parameter. */
static void start_states(Instance *in) {
#if N_STATES > 0
    if (IN(in->machine) & INITIALIZED) return;
    for (int k = 0; k < N_STATES; k++) in->values.real[STATES[k]] = in->values.real[STATE_STARTS[k]];
#else
    (void)in;
#endif
}

/* A read of the continuous state `k`, `x` its value: LK_OK; LK_WARNING, logged once until
 * the values change, where it is not a finite number (before initialisation ends it is its
 * start parameter, which may be set to anything then: that parameter is named), as every
 * read of a value that is not a number. */
static Status read_state(Instance *in, const char *call, int k, double x) {
#if N_STATES > 0
    if (isfinite(x)) return LK_OK;
    if (in->reported) return LK_WARNING;
    char value[32], at[32];
    const unsigned start = STATE_STARTS[k];
    if (!(IN(in->machine) & INITIALIZED))
        say(in, LK_WARNING, "%s: the continuous state %s reads %s: it starts at %s = %s, which "
            "is not a finite number (exitInitializationMode refuses it)", call,
            VARIABLES[STATES[k]].name, shortest(x, value, sizeof value), VARIABLES[start].name,
            shortest(in->values.real[start], at, sizeof at));
    else
        say(in, LK_WARNING, "%s: the continuous state %s reads %s at t = %s", call,
            VARIABLES[STATES[k]].name, shortest(x, value, sizeof value),
            shortest(in->time, at, sizeof at));
    in->reported = 1;
    return LK_WARNING;
#else
    (void)in, (void)call, (void)k, (void)x;
    return LK_OK;
#endif
}

/* Compute the outputs if the inputs changed: LK_OK (solved), LK_DISCARD (cannot be
 * solved; `why` says why), LK_ERROR (the parameters are invalid, or the backend failed). */
static Status evaluate(Instance *in, const char *call) {
    if (in->fresh) return in->solved ? LK_OK : LK_DISCARD;
    Status s = prepare(in, call);
    if (s != LK_OK) return s;
    start_states(in);
    in->reported = 0;
    unfit_inputs(in, in->why, sizeof in->why);
    s = LK_DISCARD;
    if (!in->why[0]) {
        s = answer(in, call, backend_evaluate(in, &in->values, in->outputs, in->why,
                                              sizeof in->why));
        if (s > LK_DISCARD) {
            return say(in, LK_ERROR, "%s: %s", call, in->why[0] ? in->why : "the backend failed");
        }
    }
    if (s == LK_DISCARD)
        for (int k = 0; k < N_OUTPUTS; k++) in->outputs[k] = NAN;
    in->fresh = 1;
    in->solved = s == LK_OK;
    return s;
}

/* Log, once per change of the inputs, why they cannot be solved (with `status`: Discard
 * from a step, Warning from a read), naming the time of the step's start. */
static void report(Instance *in, Status status, const char *call, double t) {
    if (in->reported) return;
    char inputs[1024], at[32];
    describe_inputs(in, inputs, sizeof inputs);
    say(in, status, "%s: the inputs %s cannot be solved at t = %s: %s; the outputs are NaN "
        "until an input changes", call, inputs, shortest(t, at, sizeof at), in->why);
    in->reported = 1;
}

/* -- the calls, for the adapters ------------------------------------------------------- */
/* An instance, or NULL with a log through a probe when `name`, `token` or the backend
 * refuse. `probe_in` has the adapter's fields (emit, host, memory); `resources` is the
 * resources folder as a path (FMI 3.0) or a file URI (FMI 2.0: `uri`), or NULL. */
static Instance *lk_instantiate(const char *call, const char *name, const char *token,
                                const char *resources, int uri, int logging,
                                const Instance *probe_in) {
    Instance probe = *probe_in;
    probe.name = (char *)(name && *name && utf8((const unsigned char *)name) ? name : "?");
    probe.logging = logging;
    char why[LK_PATH + 1024];
    why[0] = '\0';
    if (!name || !*name)
        snprintf(why, sizeof why, "the instance name is empty");
    else if (!utf8((const unsigned char *)name))
        snprintf(why, sizeof why, "the instance name is not valid UTF-8");
    else if (!token || strcmp(token, MODEL_GUID))
        snprintf(why, sizeof why, "the %s %s does not match this FMU's " MODEL_GUID
                 " (a modelDescription.xml of another FMU?)",
                 call[3] == '3' ? "instantiation token" : "GUID", token ? token : "(null)");
    else
        backend_ready(why, sizeof why);
    if (why[0]) {
        say(&probe, LK_ERROR, "%s: %s", call, why);
        return NULL;
    }
    Instance *in = (Instance *)probe.allocate(1, sizeof *in);
    char *copy = (char *)probe.allocate(strlen(name) + 1, 1);
    if (!in || !copy) {
        if (in) probe.release(in);
        if (copy) probe.release(copy);
        say(&probe, LK_ERROR, "%s: out of memory", call);
        return NULL;
    }
    strcpy(copy, name);
    *in = probe;
    in->name = copy;
    in->machine = S_INSTANTIATED;
    memset(&in->values, 0, sizeof in->values);
    char path[LK_PATH + 1];
    const char *folder = resources;
    if (resources && uri) folder = file_path(resources, path, sizeof path) ? path : NULL;
    if (folder && !absolute(folder)) folder = NULL;
    if (!start_values(in, &in->values) ||
        !(in->model = backend_instantiate(in, folder, resources))) {
        release_values(in, &in->values);
        probe.release(copy);
        probe.release(in);
        return NULL;
    }
    return in;
}

static void lk_free(Instance *in) {
    if (!in) return;
    while (in->states) {
        Saved *s = in->states;
        in->states = s->next;
        release_values(in, &s->values);
        memset(s->magic, 0, sizeof s->magic);
        in->release(s);
    }
    backend_free(in);
    release_values(in, &in->values);
    void (*release)(void *) = in->release;
    release(in->name);
    release(in);
}

#define INSTANCE(c, call)                                                                  \
    Instance *in = (Instance *)(c);                                                        \
    if (!in) return LK_ERROR;                                                              \
    if (in->machine == S_FAILED)                                                           \
        return say(in, LK_ERROR, "%s: this instance failed earlier and can only be freed", call);

/* The instance `c` if a call may use it; NULL (with a log if it failed earlier). */
static Instance *lk_instance(void *c, const char *call) {
    Instance *in = (Instance *)c;
    if (in && in->machine == S_FAILED) {
        say(in, LK_ERROR, "%s: this instance failed earlier and can only be freed", call);
        return NULL;
    }
    return in;
}

/* A call the model does not offer: Error, saying why. */
static Status lk_refuse(void *c, const char *call, const char *why) {
    INSTANCE(c, call);
    return say(in, LK_ERROR, "%s: not supported (%s)", call, why);
}

static Status lk_set_debug_logging(void *c, const char *call, int on, size_t n,
                                   const char *const categories[]) {
    INSTANCE(c, call);
    if (n && !categories)
        return say(in, LK_ERROR, "%s: categories is NULL with nCategories = %zu", call, n);
    unsigned mask = 0;
    for (size_t i = 0; i < n; i++) {
        unsigned k = 0;
        while (k < N_CATEGORIES && !(categories[i] && !strcmp(categories[i], LOG_CATEGORIES[k])))
            k++;
        if (k == N_CATEGORIES)
            return say(in, LK_ERROR, "%s: unknown log category '%s'; the categories are "
                       "logStatusWarning, logStatusDiscard, logStatusError, logStatusFatal, "
                       "logAll", call, categories[i] ? categories[i] : "(null)");
        mask |= 1u << k;
    }
    in->logging = on;
    in->categories = mask;
    return LK_OK;
}

/* Enter initialisation mode at `start` (FMI 2.0: SetupExperiment sets it before). */
static Status lk_setup(void *c, const char *call, int tolerance_defined, double tolerance,
                       double start, int stop_defined, double stop) {
    INSTANCE(c, call);
    if (require(in, call, IN(S_INSTANTIATED))) return LK_ERROR;
    if (!isfinite(start))
        return say(in, LK_ERROR, "%s: startTime = %g is not finite", call, start);
    if (stop_defined && !(stop >= start))
        return say(in, LK_ERROR, "%s: stopTime = %g is not >= startTime = %g", call, stop, start);
    if (tolerance_defined && !(tolerance > 0.0 && isfinite(tolerance)))
        return say(in, LK_ERROR, "%s: tolerance = %g is not a positive number", call, tolerance);
    in->time = start;
    return LK_OK;
}

/* A change of mode with nothing else to it: from one of the modes `from` to `to`. */
static Status move(Instance *in, const char *call, unsigned from, Machine to) {
    if (require(in, call, from)) return LK_ERROR;
    in->machine = to;
    return LK_OK;
}

static Status lk_enter_initialization(void *c, const char *call) {
    INSTANCE(c, call);
    return move(in, call, IN(S_INSTANTIATED), S_INIT);
}

static Status lk_exit_initialization(void *c, const char *call) {
    INSTANCE(c, call);
    if (require(in, call, IN(S_INIT))) return LK_ERROR;
    if (prepare(in, call) != LK_OK) {
        if (in->machine == S_FAILED) return LK_ERROR;
        return say(in, LK_ERROR, "%s: the parameter set is invalid: %s; the instance stays in "
                   "initialisation mode until it is fixed", call, in->problem);
    }
    start_states(in);
#if N_STATES > 0
    in->values.integer[MOTION_VR] = start_motion(&in->values);
    changed(in, 0);
#endif
    in->machine = in->event_mode_used || in->exchange ? S_EVENT : S_STEP;
    return LK_OK;
}

static Status lk_terminate(void *c, const char *call) {
    INSTANCE(c, call);
    if (require(in, call, IN(S_STEP) | IN(S_EVENT) | IN(S_CONTINUOUS))) return LK_ERROR;
    in->machine = S_TERMINATED;
    return LK_OK;
}

/* Event mode (FMI 3.0, where the importer asked for it): the model has no events, so it
 * never asks for one; entering and leaving changes nothing but the mode. FMI 3.0's calls
 * only are `inline`: FMI 2.0's unit has no use for them. */
static inline Status lk_enter_event_mode(void *c, const char *call) {
    INSTANCE(c, call);
    if (!in->event_mode_used)
        return say(in, LK_ERROR, "%s: the instance was made with eventModeUsed = false", call);
    return move(in, call, IN(S_STEP), S_EVENT);
}

static inline Status lk_enter_step_mode(void *c, const char *call) {
    INSTANCE(c, call);
    if (in->exchange) return say(in, LK_ERROR, "%s: the instance is for model exchange", call);
    return move(in, call, IN(S_EVENT), S_STEP);
}

/* One call settles an event: a co-simulation instance has no discrete state; model
 * exchange's drive (continuous.c) updates its motion, and may set omega to 0 (`*moved`). */
static inline Status lk_update_discrete_states(void *c, const char *call, int *moved) {
    INSTANCE(c, call);
    *moved = 0;
    if (require(in, call, IN(S_EVENT))) return LK_ERROR;
#if N_STATES > 0
    if (in->exchange) return drive_event(in, call, moved);
#endif
    return LK_OK;
}

static Status lk_reset(void *c, const char *call) {
    INSTANCE(c, call);
    if (!start_values(in, &in->values)) return say(in, LK_ERROR, "%s: out of memory", call);
    changed(in, 1);
    in->machine = S_INSTANTIATED;
    in->time = 0.0;
    in->discarded = 0;
    in->substep = 0.0;
    return LK_OK;
}

/* -- values ----------------------------------------------------------------------------- */
/* The outputs of the inputs in force, for a read: LK_OK; LK_WARNING, logged once, where
 * the parameter set is invalid or the inputs cannot be solved (the outputs are NaN);
 * LK_ERROR where the backend failed (and said so). */
static Status read_outputs(Instance *in, const char *call) {
    Status s = evaluate(in, call);
    if (s == LK_ERROR && (in->machine == S_FAILED || in->prepared)) return LK_ERROR;
    if (s == LK_ERROR) { /* an invalid parameter set: no outputs until it is fixed */
        if (!in->parameters_reported)
            say(in, LK_WARNING, "%s: the parameter set is invalid: %s; the outputs are NaN",
                call, in->problem);
        in->parameters_reported = 1;
        for (int k = 0; k < N_OUTPUTS; k++) in->outputs[k] = NAN;
        return LK_WARNING;
    }
    if (s == LK_DISCARD) {
        report(in, LK_WARNING, call, in->time);
        return LK_WARNING;
    }
    return LK_OK;
}

/* An output read at inputs that were solved but that has no finite value (eta where no
 * power enters): a Warning, as every read of a NaN, logged once per change of the inputs. */
static Status no_value(Instance *in, const char *call, const Variable *v, double value) {
    if (in->reported) return LK_WARNING;
    char inputs[1024], at[32], text[32];
    describe_inputs(in, inputs, sizeof inputs);
    say(in, LK_WARNING, "%s: output %s has no finite value at the inputs %s at t = %s: it "
        "reads %s", call, v->name, inputs, shortest(in->time, at, sizeof at),
        shortest(value, text, sizeof text));
    in->reported = 1;
    return LK_WARNING;
}

/* Outputs are read from the last evaluation: NaN with a Warning where the inputs cannot be
 * solved or the parameters are invalid; a Warning for any other output that is not finite:
 * no read answers OK with a value that is not a finite number. */
static Status lk_get_real(void *c, const char *call, const ValueReference vr[], size_t nvr,
                          double value[]) {
    INSTANCE(c, call);
    if (require(in, call, READABLE) || check_refs(in, call, vr, nvr, value, T_REAL, TYPE_NAMES[T_REAL]))
        return LK_ERROR;
    Status status = LK_OK;
    for (size_t i = 0; i < nvr; i++) {
        const Variable *v = &VARIABLES[vr[i]];
        if (v->kind == K_STATE) start_states(in);
        if (v->kind != K_OUTPUT) {
            value[i] = in->values.real[vr[i]];
            if (v->kind == K_STATE) {
                const Status s = read_state(in, call, v->index, value[i]);
                if (s > status) status = s;
            }
            continue;
        }
        Status s = read_outputs(in, call);
        if (s == LK_ERROR) return LK_ERROR;
        value[i] = in->outputs[v->index];
        if (s == LK_OK && !isfinite(value[i])) s = no_value(in, call, v, value[i]);
        if (s > status) status = s;
    }
    return status;
}

/* Derivatives of the outputs `unknown` along the direction `seed` of the inputs `known`
 * (`n_seed` and `n_out` values: one per variable, all scalars), exact, by forward mode
 * through the backend's kernel (backend_tangent); NaN with a Warning where the outputs
 * are (the parameter set is invalid, the inputs cannot be solved). */
static Status lk_directional(void *c, const char *call, const ValueReference unknown[],
                             size_t nu, const ValueReference known[], size_t nk,
                             const double seed[], size_t n_seed, double out[], size_t n_out) {
    INSTANCE(c, call);
#if BACKEND_TANGENT
    if (n_seed != nk || n_out != nu)
        return say(in, LK_ERROR, "%s: %zu seeds for %zu knowns and %zu sensitivities for %zu "
                   "unknowns: one per variable", call, n_seed, nk, n_out, nu);
    if (require(in, call, READABLE) || check_refs(in, call, unknown, nu, out, T_REAL,
                                                  TYPE_NAMES[T_REAL]) ||
        check_refs(in, call, known, nk, seed, T_REAL, TYPE_NAMES[T_REAL]))
        return LK_ERROR;
    double dx[N_INPUTS + 1] = {0.0}, y[N_OUTPUTS + 1], dy[N_OUTPUTS + 1];
    for (size_t i = 0; i < nu; i++)
        if (VARIABLES[unknown[i]].kind != K_OUTPUT)
            return say(in, LK_ERROR, "%s: unknown %zu, '%s' (value reference %u), is not an "
                       "output: the derivatives are those of the outputs", call, i,
                       VARIABLES[unknown[i]].name, (unsigned)unknown[i]);
    for (size_t j = 0; j < nk; j++) {
        const Variable *v = &VARIABLES[known[j]];
        char value[32];
        if (v->kind != K_INPUT)
            return say(in, LK_ERROR, "%s: known %zu, '%s' (value reference %u), is not an "
                       "input: the derivatives are with respect to the inputs", call, j,
                       v->name, (unsigned)known[j]);
        if (!isfinite(seed[j]))
            return say(in, LK_ERROR, "%s: the seed of '%s' (entry %zu) = %s is not a finite "
                       "number", call, v->name, j, shortest(seed[j], value, sizeof value));
        dx[v->index] += seed[j];
    }
    Status s = read_outputs(in, call);
    /* outputs still current need no parameter step, but the kernel's twin does: the
     * backend may hold another set's (a deserialized state's, checked) since */
    if (s == LK_OK) s = prepare(in, call);
    if (s == LK_OK) {
        char why[512] = "";
        s = answer(in, call, backend_tangent(in, &in->values, dx, y, dy, why, sizeof why));
        if (s > LK_DISCARD)
            return say(in, LK_ERROR, "%s: %s", call, why[0] ? why : "the backend failed");
        if (s == LK_DISCARD) /* the outputs are solved, their derivatives are not */
            say(in, LK_WARNING, "%s: no derivatives at these inputs: %s; they are NaN",
                call, why);
    }
    if (s == LK_ERROR) return LK_ERROR;
    for (size_t i = 0; i < nu; i++)
        out[i] = s == LK_OK ? dy[VARIABLES[unknown[i]].index] : NAN;
    return s == LK_OK ? LK_OK : LK_WARNING;
#else
    (void)unknown, (void)nu, (void)known, (void)nk, (void)seed, (void)n_seed, (void)out,
        (void)n_out;
    return say(in, LK_ERROR, "%s: this FMU provides no directional derivatives", call);
#endif
}

static Status lk_get_integer(void *c, const char *call, const ValueReference vr[], size_t nvr,
                             int value[]) {
    INSTANCE(c, call);
    if (require(in, call, READABLE) ||
        check_refs(in, call, vr, nvr, value, T_INTEGER, TYPE_NAMES[T_INTEGER]))
        return LK_ERROR;
    for (size_t i = 0; i < nvr; i++) value[i] = in->values.integer[vr[i]];
    return LK_OK;
}

static Status lk_get_string(void *c, const char *call, const ValueReference vr[], size_t nvr,
                            const char *value[]) {
    INSTANCE(c, call);
    if (require(in, call, READABLE) || check_refs(in, call, vr, nvr, value, T_STRING, TYPE_NAMES[T_STRING]))
        return LK_ERROR;
    for (size_t i = 0; i < nvr; i++) value[i] = in->values.string[vr[i]];
    return LK_OK;
}

/* A type without variables (Boolean, FMI 3.0's other types): an empty call, or Error. */
static Status lk_no_variables(void *c, const char *call, unsigned allowed,
                              const ValueReference vr[], size_t nvr, const void *value,
                              const char *type_name) {
    INSTANCE(c, call);
    if (require(in, call, allowed)) return LK_ERROR;
    return check_refs(in, call, vr, nvr, value, -1, type_name);
}

static Status lk_set_real(void *c, const char *call, const char *exit_call,
                          const ValueReference vr[], size_t nvr, const double value[]) {
    INSTANCE(c, call);
    if (require(in, call, WRITABLE) || check_refs(in, call, vr, nvr, value, T_REAL, TYPE_NAMES[T_REAL]) ||
        check_settable(in, call, vr, nvr, exit_call))
        return LK_ERROR;
    if (IN(in->machine) & INITIALIZED) { /* a tunable parameter: checked before it is taken */
        char why[512];
        for (size_t i = 0; i < nvr; i++)
            if (VARIABLES[vr[i]].kind == K_TUNABLE &&
                unfit_real(&VARIABLES[vr[i]], value[i], why, sizeof why)[0])
                return say(in, LK_ERROR, "%s: %s; it keeps its value", call, why);
    }
    for (size_t i = 0; i < nvr; i++) {
        double *stored = &in->values.real[vr[i]];
        /* a change: a different value, or a NaN (whose bits may differ) */
        if (memcmp(stored, &value[i], sizeof *stored) || value[i] != value[i])
            changed(in, VARIABLES[vr[i]].kind != K_INPUT);
        *stored = value[i];
    }
    return LK_OK;
}

static Status lk_set_integer(void *c, const char *call, const char *exit_call,
                             const ValueReference vr[], size_t nvr, const int value[]) {
    INSTANCE(c, call);
    if (require(in, call, WRITABLE) ||
        check_refs(in, call, vr, nvr, value, T_INTEGER, TYPE_NAMES[T_INTEGER]) ||
        check_settable(in, call, vr, nvr, exit_call))
        return LK_ERROR;
    char why[512];
    for (size_t i = 0; i < nvr; i++) /* check all before setting any */
        if (unfit_integer(&VARIABLES[vr[i]], value[i], why, sizeof why)[0])
            return say(in, LK_ERROR, "%s: %s", call, why);
    for (size_t i = 0; i < nvr; i++) {
        if (in->values.integer[vr[i]] != value[i]) changed(in, 1);
        in->values.integer[vr[i]] = value[i];
    }
    return LK_OK;
}

static Status lk_set_string(void *c, const char *call, const char *exit_call,
                            const ValueReference vr[], size_t nvr, const char *const value[]) {
    INSTANCE(c, call);
    if (require(in, call, WRITABLE) || check_refs(in, call, vr, nvr, value, T_STRING, TYPE_NAMES[T_STRING]) ||
        check_settable(in, call, vr, nvr, exit_call))
        return LK_ERROR;
    char why[512];
    for (size_t i = 0; i < nvr; i++) /* check all before setting any */
        if (unfit_string(&VARIABLES[vr[i]], value[i], why, sizeof why)[0])
            return say(in, LK_ERROR, "%s: %s", call, why);
    for (size_t i = 0; i < nvr; i++) {
        char *copy = copy_text(in, value[i]);
        if (!copy) return say(in, LK_ERROR, "%s: out of memory", call);
        if (strcmp(in->values.string[vr[i]], copy)) changed(in, 1);
        in->release(in->values.string[vr[i]]);
        in->values.string[vr[i]] = copy;
    }
    return LK_OK;
}

/* The variables `vr` depends on, as the modelDescription's ModelStructure declares them:
 * an output's inputs (with every parameter before initialisation ends); none for the
 * others (FMI 3.0's). */
static inline Status lk_dependencies(void *c, const char *call, ValueReference vr,
                                     const ValueReference **list, size_t *n) {
    INSTANCE(c, call);
    if (vr >= N_VARIABLES || !VARIABLES[vr].name)
        return say(in, LK_ERROR, "%s: value reference %u is not a variable of " MODEL_IDENTIFIER,
                   call, (unsigned)vr);
    const Variable *v = &VARIABLES[vr];
    const int initial = in->machine == S_INSTANTIATED || in->machine == S_INIT;
    *list = initial ? v->initial : v->depends;
    *n = (size_t)(initial ? v->n_initial : v->n_depends);
    return LK_OK;
}

/* -- stepping --------------------------------------------------------------------------- */
/* One step from `t` to `t + h`: LK_OK, or LK_DISCARD where the inputs cannot be solved
 * (the time stays at `t`). */
static Status lk_do_step(void *c, const char *call, double t, double h) {
    INSTANCE(c, call);
    if (require(in, call, IN(S_STEP))) return LK_ERROR;
    if (!isfinite(t))
        return say(in, LK_ERROR, "%s: currentCommunicationPoint = %g is not finite", call, t);
    if (!(h > 0.0) || !isfinite(h))
        return say(in, LK_ERROR, "%s: communicationStepSize = %g is not a positive finite number",
                   call, h);
#if N_STATES > 0
    return advance(in, call, t, h); /* continuous.c */
#endif
    Status s = evaluate(in, call);
    if (s == LK_ERROR) {
        if (in->machine != S_FAILED && !in->prepared)
            say(in, LK_ERROR, "%s: the parameter set is invalid: %s", call, in->problem);
        return LK_ERROR;
    }
    in->discarded = s == LK_DISCARD;
    if (s == LK_DISCARD) {
        report(in, LK_DISCARD, call, t);
        return LK_DISCARD;
    }
    in->time = t + h;
    return LK_OK;
}

/* -- FMU states ------------------------------------------------------------------------ */
/* `state` if it is a live state of this instance, else NULL (with a log). */
static Saved *live_state(const Instance *in, const char *call, const void *state) {
    if (!state) {
        say(in, LK_ERROR, "%s: the FMU state is NULL", call);
        return NULL;
    }
    for (Saved *s = in->states; s; s = s->next)
        if (s == state) return s;
    say(in, LK_ERROR, "%s: %p is not an FMU state of this instance (freed, or another "
        "instance's)", call, state);
    return NULL;
}

static Status lk_get_state(void *c, const char *call, void **state) {
    INSTANCE(c, call);
    if (!state) return say(in, LK_ERROR, "%s: the state pointer is NULL", call);
    Saved *s = NULL;
    if (*state) { /* update a state returned before, in place */
        if (!(s = live_state(in, call, *state))) return LK_ERROR;
    } else {
        s = (Saved *)in->allocate(1, sizeof *s);
        if (!s) return say(in, LK_ERROR, "%s: out of memory", call);
        memcpy(s->magic, STATE_MAGIC, sizeof STATE_MAGIC);
        s->owner = in;
    }
    if (!copy_values(in, &s->values, &in->values)) {
        if (!*state) in->release(s);
        return say(in, LK_ERROR, "%s: out of memory", call);
    }
    s->machine = in->machine;
    s->time = in->time;
    s->substep = in->substep;
    if (!*state) {
        s->next = in->states;
        in->states = s;
        *state = s;
    }
    return LK_OK;
}

/* Take the values, time and mode of a saved state whole. */
static Status restore(Instance *in, const char *call, const Values *values, Machine machine,
                      double time, double substep) {
    if (!copy_values(in, &in->values, values)) return say(in, LK_ERROR, "%s: out of memory", call);
    changed(in, 1);
    in->machine = machine;
    in->time = time;
    in->substep = substep;
    in->discarded = 0;
    return LK_OK;
}

static Status lk_set_state(void *c, const char *call, void *state) {
    INSTANCE(c, call);
    Saved *s = live_state(in, call, state);
    if (!s) return LK_ERROR;
    return restore(in, call, &s->values, s->machine, s->time, s->substep);
}

/* Unlink the live state `s` from the instance and release it. */
static void drop_state(Instance *in, Saved *s) {
    for (Saved **p = &in->states; *p; p = &(*p)->next)
        if (*p == s) {
            *p = s->next;
            break;
        }
    release_values(in, &s->values);
    memset(s->magic, 0, sizeof s->magic);
    in->release(s);
}

static Status lk_free_state(void *c, const char *call, void **state) {
    INSTANCE(c, call);
    if (!state) return say(in, LK_ERROR, "%s: the state pointer is NULL", call);
    /* Given the state itself rather than its address, as fmusim 0.0.39 does when it saves
     * or restores a state file: a live state's address is never an importer's variable,
     * so this is recognised without reading through it, and the state is freed: OK, as
     * the call did what was meant (fmusim stops at a Warning), with the mistake logged. */
    for (Saved *s = in->states; s; s = s->next)
        if ((void *)s == (void *)state) {
            drop_state(in, s);
            say(in, LK_WARNING, "%s: given the FMU state itself instead of a pointer to it; "
                "it is freed", call);
            return LK_OK;
        }
    if (!*state) return LK_OK;
    Saved *s = live_state(in, call, *state);
    if (!s) return LK_ERROR;
    drop_state(in, s);
    *state = NULL;
    return LK_OK;
}

/* Serialized layout: magic[8] | u32 format | u32 nid | id | u32 nguid | guid | u32 mode
 * (Machine: 0 Instantiated, 1 InitializationMode, 2 step mode, 3 Terminated, 4 EventMode,
 * 6 ContinuousTimeMode) | f64 time | with continuous states (format 3), f64 the
 * integrator's next substep | per input, parameter and continuous state by value
 * reference: a real f64, an integer i32, a string u32 length + bytes | u32 CRC-32 of all
 * bytes before it. */
static int kept(const Variable *v) { return v->name && v->kind != K_OUTPUT; }

static uint32_t crc32(const unsigned char *p, size_t n) {
    uint32_t crc = 0xFFFFFFFFu;
    while (n--) {
        crc ^= *p++;
        for (int k = 0; k < 8; k++) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
    }
    return ~crc;
}

static size_t serialized_size(const Saved *s) {
    size_t n = 8 + 4 + 4 + strlen(MODEL_IDENTIFIER) + 4 + strlen(MODEL_GUID) + 4 + 8 + 4 +
               (N_STATES ? 8 : 0);
    for (unsigned vr = 0; vr < N_VARIABLES; vr++) {
        const Variable *v = &VARIABLES[vr];
        if (!kept(v)) continue;
        n += v->type == T_REAL ? 8 : v->type == T_INTEGER ? 4
             : v->type == T_STRING ? 4 + strlen(s->values.string[vr]) : 0;
    }
    return n;
}

static Status lk_state_size(void *c, const char *call, void *state, size_t *size) {
    INSTANCE(c, call);
    if (!size) return say(in, LK_ERROR, "%s: size is NULL", call);
    Saved *s = live_state(in, call, state);
    if (!s) return LK_ERROR;
    *size = serialized_size(s);
    return LK_OK;
}

static unsigned char *put(unsigned char *p, const void *v, size_t n) {
    memcpy(p, v, n);
    return p + n;
}

static Status lk_serialize(void *c, const char *call, void *state, unsigned char *bytes,
                           size_t size) {
    INSTANCE(c, call);
    Saved *s = live_state(in, call, state);
    if (!s) return LK_ERROR;
    if (!bytes) return say(in, LK_ERROR, "%s: the byte array is NULL", call);
    if (size != serialized_size(s))
        return say(in, LK_ERROR, "%s: size = %zu, but the state needs %zu bytes", call, size,
                   serialized_size(s));
    uint32_t format = STATE_FORMAT, nid = (uint32_t)strlen(MODEL_IDENTIFIER),
             nguid = (uint32_t)strlen(MODEL_GUID), mode = (uint32_t)s->machine;
    unsigned char *p = put(bytes, STATE_MAGIC, 8);
    p = put(p, &format, 4);
    p = put(p, &nid, 4);
    p = put(p, MODEL_IDENTIFIER, nid);
    p = put(p, &nguid, 4);
    p = put(p, MODEL_GUID, nguid);
    p = put(p, &mode, 4);
    p = put(p, &s->time, 8);
    if (N_STATES) p = put(p, &s->substep, 8);
    for (unsigned vr = 0; vr < N_VARIABLES; vr++) {
        const Variable *v = &VARIABLES[vr];
        if (!kept(v)) continue;
        if (v->type == T_REAL) p = put(p, &s->values.real[vr], 8);
        else if (v->type == T_INTEGER) p = put(p, &s->values.integer[vr], 4);
        else if (v->type == T_STRING) {
            uint32_t n = (uint32_t)strlen(s->values.string[vr]);
            p = put(p, &n, 4);
            p = put(p, s->values.string[vr], n);
        }
    }
    uint32_t crc = crc32(bytes, (size_t)(p - bytes));
    put(p, &crc, 4);
    return LK_OK;
}

/* 1 if an instance of this kind (co-simulation with or without event mode, or model
 * exchange) can be in the serialized `mode`. */
static int mode_of_instance(const Instance *in, uint32_t mode) {
    if (mode == S_INSTANTIATED || mode == S_INIT || mode == S_TERMINATED) return 1;
    if (mode == S_EVENT) return in->event_mode_used || in->exchange;
    if (mode == S_STEP) return !in->exchange;
    return mode == S_CONTINUOUS && in->exchange;
}

/* Read `n` bytes at *p within [*p, end); 0 where they run past the end. */
static int take(const unsigned char **p, const unsigned char *end, void *to, size_t n) {
    if ((size_t)(end - *p) < n) return 0;
    memcpy(to, *p, n);
    *p += n;
    return 1;
}

/* Every field of a serialized state checked against this model before any is taken: the
 * frame, the mode, the time, each value (its type's and its variable's rules: UTF-8, the
 * options of a string, the allowed integers, the parameter rules and, for a state past
 * initialisation, the backend's own check of the parameter set). */
static Status lk_deserialize(void *c, const char *call, const unsigned char *b, size_t size,
                             void **state) {
    INSTANCE(c, call);
    if (!b || !state) return say(in, LK_ERROR, "%s: %s is NULL", call, !state ? "state" : "the bytes");
    /* A live state given is overwritten in place. The standards leave what *state holds
     * on entry undefined (importers pass NULL, or an uninitialised variable), so any other
     * value is not read and a new state is made. */
    Saved *reused = NULL;
    for (Saved *s = in->states; s && *state; s = s->next)
        if (s == *state) reused = s;
    const unsigned char *p = b, *end = b + size;
    char magic[8], why[1024];
    uint32_t format, nid, nguid, mode, crc;
    double time, substep = 0.0;
    if (size < 12 || !take(&p, end, magic, 8) || memcmp(magic, STATE_MAGIC, 8))
        return say(in, LK_ERROR, "%s: these %zu bytes are not a serialized linkage_fmu state",
                   call, size);
    memcpy(&crc, end - 4, 4);
    if (crc != crc32(b, size - 4))
        return say(in, LK_ERROR, "%s: checksum mismatch: the serialized state is corrupted", call);
    end -= 4;
    if (!take(&p, end, &format, 4) || format != STATE_FORMAT)
        return say(in, LK_ERROR, "%s: the state is not of format %u, which this FMU reads",
                   call, STATE_FORMAT);
    if (!take(&p, end, &nid, 4) || nid != strlen(MODEL_IDENTIFIER) || (size_t)(end - p) < nid ||
        memcmp(p, MODEL_IDENTIFIER, nid))
        return say(in, LK_ERROR, "%s: the state is not of model " MODEL_IDENTIFIER, call);
    p += nid;
    if (!take(&p, end, &nguid, 4) || nguid != strlen(MODEL_GUID) ||
        (size_t)(end - p) < nguid || memcmp(p, MODEL_GUID, nguid))
        return say(in, LK_ERROR, "%s: the state was made by another build of " MODEL_IDENTIFIER
                   " (its GUID or instantiation token differs)", call);
    p += nguid;
    if (!take(&p, end, &mode, 4) || !take(&p, end, &time, 8) ||
        (N_STATES && !take(&p, end, &substep, 8)))
        return say(in, LK_ERROR, "%s: the state is truncated", call);
    if (!mode_of_instance(in, mode))
        return say(in, LK_ERROR, "%s: the state's mode %u is not a mode of this instance%s", call,
                   (unsigned)mode, mode == S_EVENT && !in->exchange
                   ? " (made with eventModeUsed = false)" : "");
    if (!isfinite(time)) return say(in, LK_ERROR, "%s: the state's time is not finite", call);
    if (!(substep >= 0.0) || !isfinite(substep))
        return say(in, LK_ERROR, "%s: the state's integrator substep is not a number >= 0", call);
    Saved *s = (Saved *)in->allocate(1, sizeof *s);
    if (!s) return say(in, LK_ERROR, "%s: out of memory", call);
    why[0] = '\0';
    for (unsigned vr = 0; vr < N_VARIABLES && !why[0]; vr++) {
        const Variable *v = &VARIABLES[vr];
        if (!kept(v)) continue;
        if (v->type == T_REAL) {
            if (!take(&p, end, &s->values.real[vr], 8)) snprintf(why, sizeof why, "it is truncated");
            else if (v->kind == K_STATE && !isfinite(s->values.real[vr]))
                snprintf(why, sizeof why, "the continuous state %s is not finite", v->name);
        } else if (v->type == T_INTEGER) {
            if (!take(&p, end, &s->values.integer[vr], 4)) snprintf(why, sizeof why, "it is truncated");
            else unfit_integer(v, s->values.integer[vr], why, sizeof why);
        } else if (v->type == T_STRING) {
            uint32_t n;
            if (!take(&p, end, &n, 4) || (size_t)(end - p) < n) {
                snprintf(why, sizeof why, "it is truncated");
            } else if (!(s->values.string[vr] = (char *)in->allocate((size_t)n + 1, 1))) {
                snprintf(why, sizeof why, "out of memory");
            } else {
                memcpy(s->values.string[vr], p, n);
                p += n;
                if (memchr(s->values.string[vr], '\0', n))
                    snprintf(why, sizeof why, "the value of '%s' holds a NUL byte", v->name);
                else
                    unfit_string(v, s->values.string[vr], why, sizeof why);
            }
        }
    }
    if (!why[0] && p != end) snprintf(why, sizeof why, "it has %zu bytes too many", (size_t)(end - p));
    if (!why[0] && (IN(mode) & INITIALIZED)) { /* past initialisation: a valid set */
        if (!unfit_parameters(&s->values, why, sizeof why)[0]) {
            Status ok = answer(in, call, backend_prepare(in, &s->values, why, sizeof why));
            in->prepared = 0; /* the backend holds the state's parameters now, not ours */
            if (ok != LK_OK && !why[0]) snprintf(why, sizeof why, "the backend refused them");
        }
    }
    if (why[0]) {
        release_values(in, &s->values);
        in->release(s);
        return say(in, LK_ERROR, "%s: the state does not fit " MODEL_IDENTIFIER ": %s", call, why);
    }
    s->machine = (Machine)mode;
    s->time = time;
    s->substep = substep;
    if (reused) { /* taken whole: the old values go, the new ones take their place */
        release_values(in, &reused->values);
        reused->values = s->values;
        reused->machine = s->machine;
        reused->time = s->time;
        reused->substep = s->substep;
        in->release(s);
        return LK_OK;
    }
    memcpy(s->magic, STATE_MAGIC, sizeof STATE_MAGIC);
    s->owner = in;
    s->next = in->states;
    in->states = s;
    *state = s;
    return LK_OK;
}

#if N_STATES > 0
#include "continuous.c"
#endif
