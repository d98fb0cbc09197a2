/* The FMI framework of linkage_fmu's FMUs, in neutral types.
 *
 * fmi2.c and fmi3.c are thin adapters: each converts its standard's types and calls the
 * framework (framework.c), which owns everything the two standards share — the state
 * machine, the checks of every argument, the variables' values, the dirty flag, the
 * status policy for inputs that cannot be solved, logging, and FMU states — over one
 * backend (backend_native.c: the linkage's C kernels; backend_pythonfmu.c: the Python
 * slave through pythonfmu's wrapper). An FMU's config.h (generated) names the model,
 * its variables and its backend. Everything is one translation unit: the adapter
 * includes config.h and framework.c; framework.c includes the backend.
 */
#ifndef LINKAGE_FMU_FRAMEWORK_H
#define LINKAGE_FMU_FRAMEWORK_H

#include <math.h>
#include <stddef.h>

/* The status codes of FMI 2.0 and 3.0 have these values in both standards. */
typedef enum { LK_OK, LK_WARNING, LK_DISCARD, LK_ERROR, LK_FATAL } Status;
typedef unsigned int ValueReference;

enum { T_REAL, T_INTEGER, T_BOOLEAN, T_STRING };
/* what a variable is, for the rules on setting it (K_STATE: a continuous state, kept with
 * the values, set only by the model-exchange call or from its start parameter;
 * K_DISCRETE: a discrete state, kept with the values, changed by the model only) */
enum { K_INPUT, K_FIXED, K_TUNABLE, K_OUTPUT, K_OTHER, K_STATE, K_DISCRETE };
/* the rule a real parameter's value meets */
enum { RULE_FINITE, RULE_POSITIVE, RULE_NONNEGATIVE, RULE_SIGN };

typedef struct {
    int type;
    int kind;
    const char *name;
    const char *meaning;           /* for messages */
    int index;                     /* position among the inputs, parameters or outputs */
    double start;                  /* a real's start value */
    int rule;                      /* a real parameter's rule */
    double min, max;               /* a real parameter's bounds */
    int integer_start;
    const int *allowed;            /* an integer's allowed values, n_allowed of them */
    int n_allowed;
    const char *string_start;
    const char *const *options;    /* a string's allowed values, NULL-terminated */
    const char *rule_text;         /* an integer's or a string's allowed values, in words */
    const ValueReference *depends; /* an output's dependencies after initialisation */
    int n_depends;
    const ValueReference *initial; /* ... and in initialisation mode */
    int n_initial;
} Variable;

#endif
