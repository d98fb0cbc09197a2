/* FMI 2.0 co-simulation (and model exchange, for a model with continuous states): the
 * adapter of framework.c (which owns the state machine, the checks, the values, the status
 * policy, the states and the continuous states) to FMI 2.0's functions and types.
 *
 * What is FMI 2.0's own: the host's callbacks (its logger takes a printf format: a '%' in
 * a message is doubled; its memory functions), SetupExperiment before
 * EnterInitializationMode, the status queries fmi2Terminated (true after a discarded
 * step, until a step succeeds: fmpy then ends a run instead of retrying the same inputs
 * for ever) and fmi2LastSuccessfulTime (every other kind is fmi2Discard, as 4.2.3 says of
 * a status the slave cannot give), and the resource location as a file URI.
 */
#include "fmi2Functions.h"
#include "framework.h"
#include "config.h"
#define STEP_MODE_NAME "StepComplete"
#define TYPE_NAME_REAL "Real"
#define TYPE_NAME_INTEGER "Integer"
#include "framework.c"

/* the framework's types are FMI 2.0's, and the host's callbacks fit in an instance */
typedef char fmi2_types_match[(sizeof(fmi2ValueReference) == sizeof(ValueReference) &&
                               sizeof(fmi2Integer) == sizeof(int) && fmi2OK == (int)LK_OK &&
                               fmi2Fatal == (int)LK_FATAL &&
                               sizeof(fmi2CallbackFunctions) <= sizeof((Instance *)0)->host)
                              ? 1 : -1];

#define VR(vr) ((const ValueReference *)(vr))
#define EXIT "fmi2ExitInitializationMode"

static void emit2(const Instance *in, Status status, const char *category, const char *message) {
    const fmi2CallbackFunctions *host = (const fmi2CallbackFunctions *)in->host;
    if (!host->logger) return;
    char text[4096];
    size_t n = 0;
    for (const char *p = message; *p && n + 2 < sizeof text; p++) {
        if (*p == '%') text[n++] = '%';
        text[n++] = *p;
    }
    text[n] = '\0';
    host->logger(host->componentEnvironment, in->name, (fmi2Status)status, category, text);
}

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation,
                              const fmi2CallbackFunctions *functions, fmi2Boolean visible,
                              fmi2Boolean loggingOn) {
    (void)visible;
    if (!functions || !functions->allocateMemory || !functions->freeMemory) return NULL;
    Instance probe = {0};
    memcpy(probe.host, functions, sizeof *functions);
    probe.emit = emit2;
    probe.allocate = functions->allocateMemory;
    probe.release = functions->freeMemory;
    probe.exchange = N_STATES > 0 && fmuType == fmi2ModelExchange;
    if (fmuType != fmi2CoSimulation && !probe.exchange) {
        probe.name = (char *)"?";
        say(&probe, LK_ERROR, "fmi2Instantiate: " MODEL_IDENTIFIER " supports co-simulation only");
        return NULL;
    }
    return lk_instantiate("fmi2Instantiate", instanceName, fmuGUID, fmuResourceLocation, 1,
                          loggingOn, &probe);
}

void fmi2FreeInstance(fmi2Component c) { lk_free((Instance *)c); }

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean loggingOn, size_t nCategories,
                               const fmi2String categories[]) {
    return (fmi2Status)lk_set_debug_logging(c, "fmi2SetDebugLogging", loggingOn, nCategories,
                                            categories);
}

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                               fmi2Real startTime, fmi2Boolean stopTimeDefined,
                               fmi2Real stopTime) {
    return (fmi2Status)lk_setup(c, "fmi2SetupExperiment", toleranceDefined, tolerance, startTime,
                                stopTimeDefined, stopTime);
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c) {
    return (fmi2Status)lk_enter_initialization(c, "fmi2EnterInitializationMode");
}

fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
    return (fmi2Status)lk_exit_initialization(c, EXIT);
}

fmi2Status fmi2Terminate(fmi2Component c) { return (fmi2Status)lk_terminate(c, "fmi2Terminate"); }
fmi2Status fmi2Reset(fmi2Component c) { return (fmi2Status)lk_reset(c, "fmi2Reset"); }

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                       fmi2Real value[]) {
    return (fmi2Status)lk_get_real(c, "fmi2GetReal", VR(vr), nvr, value);
}

fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                          fmi2Integer value[]) {
    return (fmi2Status)lk_get_integer(c, "fmi2GetInteger", VR(vr), nvr, value);
}

fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                          fmi2Boolean value[]) {
    return (fmi2Status)lk_no_variables(c, "fmi2GetBoolean", READABLE, VR(vr), nvr, value,
                                       "Boolean");
}

fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                         fmi2String value[]) {
    return (fmi2Status)lk_get_string(c, "fmi2GetString", VR(vr), nvr, value);
}

fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                       const fmi2Real value[]) {
    return (fmi2Status)lk_set_real(c, "fmi2SetReal", EXIT, VR(vr), nvr, value);
}

fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                          const fmi2Integer value[]) {
    return (fmi2Status)lk_set_integer(c, "fmi2SetInteger", EXIT, VR(vr), nvr, value);
}

fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                          const fmi2Boolean value[]) {
    return (fmi2Status)lk_no_variables(c, "fmi2SetBoolean", WRITABLE, VR(vr), nvr, value,
                                       "Boolean");
}

fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                         const fmi2String value[]) {
    return (fmi2Status)lk_set_string(c, "fmi2SetString", EXIT, VR(vr), nvr, value);
}

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real currentCommunicationPoint,
                      fmi2Real communicationStepSize, fmi2Boolean noSetFMUStatePriorToCurrentPoint) {
    (void)noSetFMUStatePriorToCurrentPoint;
    return (fmi2Status)lk_do_step(c, "fmi2DoStep", currentCommunicationPoint,
                                  communicationStepSize);
}

fmi2Status fmi2CancelStep(fmi2Component c) {
    return (fmi2Status)lk_refuse(c, "fmi2CancelStep", "no step is pending: doStep never "
                                 "returns fmi2Pending");
}

/* -- status queries ------------------------------------------------------------------
 * Two statuses can be retrieved: fmi2LastSuccessfulTime (a Real) and fmi2Terminated (a
 * Boolean). Every other kind, or a known kind asked of the other functions, is a status
 * this slave cannot give, which FMI 2.0 (4.2.3) answers with fmi2Discard: the same answer,
 * with a log naming the kind and why, whatever the kind's number (-1 included). */
static const char *status_kind_name(int kind) {
    static const char *const NAMES[] = {"fmi2DoStepStatus", "fmi2PendingStatus",
                                        "fmi2LastSuccessfulTime", "fmi2Terminated"};
    return kind >= 0 && kind < 4 ? NAMES[kind] : NULL;
}

/* The instance if `kind` is the one status `known` of the call (-1: none) and `value` is
 * given, else NULL with the call's answer in *status. */
static Instance *query(fmi2Component c, const char *call, int kind, int known, const void *value,
                       fmi2Status *status) {
    Instance *in = lk_instance(c, call);
    *status = fmi2Error;
    if (!in) return NULL;
    if (!value) {
        say(in, LK_ERROR, "%s: value is NULL", call);
        return NULL;
    }
    if (known >= 0 && kind == known) return in;
    const char *name = status_kind_name(kind);
    const char *why = !name ? "it is not an fmi2StatusKind"
                      : kind <= 1 ? "doStep never returns fmi2Pending"
                      : kind == 2 ? "fmi2LastSuccessfulTime is fmi2GetRealStatus's"
                                  : "fmi2Terminated is fmi2GetBooleanStatus's";
    *status = (fmi2Status)say(in, LK_DISCARD, "%s: status kind %d%s%s%s cannot be retrieved: %s "
                              "(this slave gives fmi2LastSuccessfulTime and fmi2Terminated)",
                              call, kind, name ? " (" : "", name ? name : "", name ? ")" : "",
                              why);
    return NULL;
}

fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status *value) {
    fmi2Status status;
    query(c, "fmi2GetStatus", s, -1, value, &status);
    return status;
}

fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real *value) {
    fmi2Status status;
    Instance *in = query(c, "fmi2GetRealStatus", s, fmi2LastSuccessfulTime, value, &status);
    if (!in) return status;
    *value = in->time;
    return fmi2OK;
}

fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s, fmi2Integer *value) {
    fmi2Status status;
    query(c, "fmi2GetIntegerStatus", s, -1, value, &status);
    return status;
}

fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s, fmi2Boolean *value) {
    fmi2Status status;
    Instance *in = query(c, "fmi2GetBooleanStatus", s, fmi2Terminated, value, &status);
    if (!in) return status;
    /* after a discarded step the slave asks to end the run; a later valid step is taken */
    *value = in->discarded ? fmi2True : fmi2False;
    return fmi2OK;
}

fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind s, fmi2String *value) {
    fmi2Status status;
    query(c, "fmi2GetStringStatus", s, -1, value, &status);
    return status;
}

/* -- not offered (the capability flags say so) -------------------------------------- */
fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                       const fmi2Integer order[], const fmi2Real value[]) {
    (void)vr, (void)nvr, (void)order, (void)value;
    return (fmi2Status)lk_refuse(c, "fmi2SetRealInputDerivatives", "canInterpolateInputs is "
                                 "false");
}

fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[],
                                        size_t nvr, const fmi2Integer order[], fmi2Real value[]) {
    (void)vr, (void)nvr, (void)order, (void)value;
    return (fmi2Status)lk_refuse(c, "fmi2GetRealOutputDerivatives", "maxOutputDerivativeOrder "
                                 "is 0");
}

fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference vUnknown[],
                                        size_t nUnknown, const fmi2ValueReference vKnown[],
                                        size_t nKnown, const fmi2Real dvKnown[],
                                        fmi2Real dvUnknown[]) {
    return (fmi2Status)lk_directional(c, "fmi2GetDirectionalDerivative", VR(vUnknown), nUnknown,
                                      VR(vKnown), nKnown, dvKnown, nKnown, dvUnknown,
                                      nUnknown);
}

/* -- FMU states ------------------------------------------------------------------------ */
fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *state) {
    return (fmi2Status)lk_get_state(c, "fmi2GetFMUstate", state);
}

fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate state) {
    return (fmi2Status)lk_set_state(c, "fmi2SetFMUstate", state);
}

fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *state) {
    return (fmi2Status)lk_free_state(c, "fmi2FreeFMUstate", state);
}

fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate state, size_t *size) {
    return (fmi2Status)lk_state_size(c, "fmi2SerializedFMUstateSize", state, size);
}

fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate state, fmi2Byte bytes[],
                                 size_t size) {
    return (fmi2Status)lk_serialize(c, "fmi2SerializeFMUstate", state, (unsigned char *)bytes,
                                    size);
}

fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte serializedState[], size_t size,
                                   fmi2FMUstate *state) {
    return (fmi2Status)lk_deserialize(c, "fmi2DeSerializeFMUstate",
                                      (const unsigned char *)serializedState, size, state);
}

#if N_STATES > 0
/* -- model exchange ------------------------------------------------------------------------ */
fmi2Status fmi2EnterEventMode(fmi2Component c) {
    return (fmi2Status)lk_exchange_event_mode(c, "fmi2EnterEventMode");
}

fmi2Status fmi2NewDiscreteStates(fmi2Component c, fmi2EventInfo *eventInfo) {
    Instance *in = lk_instance(c, "fmi2NewDiscreteStates");
    if (!in) return fmi2Error;
    if (!eventInfo) return (fmi2Status)say(in, LK_ERROR, "fmi2NewDiscreteStates: eventInfo is NULL");
    int moved;
    Status s = lk_update_discrete_states(in, "fmi2NewDiscreteStates", &moved);
    if (s != LK_OK) return (fmi2Status)s;
    memset(eventInfo, 0, sizeof *eventInfo); /* settled in one call; no time events */
    eventInfo->valuesOfContinuousStatesChanged = moved ? fmi2True : fmi2False;
    return fmi2OK;
}

fmi2Status fmi2EnterContinuousTimeMode(fmi2Component c) {
    return (fmi2Status)lk_enter_continuous_time_mode(c, "fmi2EnterContinuousTimeMode");
}

fmi2Status fmi2CompletedIntegratorStep(fmi2Component c, fmi2Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi2Boolean *enterEventMode,
                                       fmi2Boolean *terminateSimulation) {
    (void)noSetFMUStatePriorToCurrentPoint;
    Instance *in = lk_instance(c, "fmi2CompletedIntegratorStep");
    if (!in) return fmi2Error;
    if (!enterEventMode || !terminateSimulation)
        return (fmi2Status)say(in, LK_ERROR, "fmi2CompletedIntegratorStep: %s is NULL",
                               !enterEventMode ? "enterEventMode" : "terminateSimulation");
    Status s = lk_completed_integrator_step(in, "fmi2CompletedIntegratorStep");
    if (s == LK_OK) *enterEventMode = *terminateSimulation = fmi2False;
    return (fmi2Status)s;
}

fmi2Status fmi2SetTime(fmi2Component c, fmi2Real time) {
    return (fmi2Status)lk_set_time(c, "fmi2SetTime", time);
}

fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t nx) {
    return (fmi2Status)lk_set_continuous_states(c, "fmi2SetContinuousStates", x, nx);
}

fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real derivatives[], size_t nx) {
    return (fmi2Status)lk_get_derivatives(c, "fmi2GetDerivatives", derivatives, nx);
}

fmi2Status fmi2GetEventIndicators(fmi2Component c, fmi2Real eventIndicators[], size_t ni) {
    return (fmi2Status)lk_get_event_indicators(c, "fmi2GetEventIndicators", eventIndicators, ni);
}

fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t nx) {
    return (fmi2Status)lk_get_continuous_states(c, "fmi2GetContinuousStates", x, nx);
}

fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component c, fmi2Real x_nominal[], size_t nx) {
    return (fmi2Status)lk_get_nominals(c, "fmi2GetNominalsOfContinuousStates", x_nominal, nx);
}
#endif
