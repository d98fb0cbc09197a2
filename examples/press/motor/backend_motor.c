/* The backend of the press's motor FMU for linkage_fmu's FMI framework (framework.c owns
 * the state machine, the checks, the values and the status policy; config.h, written by
 * examples/press/motor.py, names the variables).
 *
 * The motor is algebraic: its linear torque-speed line, referred to the crank,
 *     tau = T_stall * (1 - omega / omega_noload),
 * and the power it puts into the crank, P = tau * omega. Its rotor's inertia is not here:
 * it turns with the crank, so the system gives it to the press as an inertia on the crank
 * (the drive FMU's J1), which keeps the coupled system an ODE in the press's own states.
 */

typedef struct {
    double T_stall, omega_noload;
} Model;

static int backend_ready(char *why, size_t size) {
    (void)why, (void)size;
    return 1;
}

static void *backend_instantiate(Instance *in, const char *resources, const char *location) {
    (void)resources, (void)location; /* the line needs no file */
    Model *m = (Model *)in->allocate(1, sizeof *m);
    if (!m) say(in, LK_ERROR, "out of memory");
    return m;
}

static void backend_free(Instance *in) { in->release(in->model); }

/* The framework has checked both parameters against their rule (> 0, finite). */
static Status backend_prepare(Instance *in, const Values *v, char *why, size_t size) {
    (void)why, (void)size;
    Model *m = (Model *)in->model;
    m->T_stall = v->real[VR_T_STALL];
    m->omega_noload = v->real[VR_OMEGA_NOLOAD];
    return LK_OK;
}

static Status backend_evaluate(Instance *in, const Values *v, double *y, char *why,
                               size_t size) {
    const Model *m = (const Model *)in->model;
    const double omega = v->real[VR_OMEGA];
    const double tau = m->T_stall * (1.0 - omega / m->omega_noload);
    y[Y_TAU] = tau;
    y[Y_POWER] = tau * omega;
    if (!isfinite(y[Y_TAU]) || !isfinite(y[Y_POWER])) {
        set_text(why, size, "the motor's torque or power overflows float64: the crank speed "
                 "is too large in magnitude");
        return LK_DISCARD;
    }
    return LK_OK;
}
