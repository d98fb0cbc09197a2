/* FMI 3.0 co-simulation (and model exchange, for a model with continuous states): the
 * adapter of framework.c (which owns the state machine, the checks, the values, the status
 * policy, the states and the continuous states) to FMI 3.0's functions and types.
 *
 * What is FMI 3.0's own:
 * - the independent variable `time`, value reference N_VARIABLES (right after the
 *   variable table): read from the last successful communication point, never set;
 * - nValues, which must equal nValueReferences (every variable is a scalar);
 * - the logger, which takes plain text, and memory from calloc and free;
 * - EnterInitializationMode with the experiment's times, and DoStep's out-arguments: a
 *   discarded step sets lastSuccessfulTime to its start and terminateSimulation;
 * - event mode, for an importer that instantiates with eventModeUsed (hasEventMode is
 *   true): DoStep never asks for an event (a drive FMU's stops are handled inside it),
 *   UpdateDiscreteStates changes nothing in co-simulation and EnterStepMode goes back
 *   to steps; in model exchange it is the drive's event update (continuous.c);
 * - the variables' dependencies (providesPerElementDependencies), those of the
 *   modelDescription's ModelStructure, from config.h's table;
 * - every FMI 3.0 function is exported: what the model has not (model exchange without
 *   continuous states, scheduled execution, clocks, configuration mode, derivatives, the types it has no
 *   variables of) answers fmi3Error (or NULL) with a log.
 */
#include "fmi3Functions.h"
#include "framework.h"
#include "config.h"
#define STEP_MODE_NAME "StepMode"
#define TYPE_NAME_REAL "Float64"
#define TYPE_NAME_INTEGER "Int32"
#include "framework.c"

/* the framework's types are FMI 3.0's */
typedef char fmi3_types_match[(sizeof(fmi3ValueReference) == sizeof(ValueReference) &&
                               sizeof(fmi3Int32) == sizeof(int) && fmi3OK == (int)LK_OK &&
                               fmi3Fatal == (int)LK_FATAL) ? 1 : -1];

#define TIME_VR ((fmi3ValueReference)N_VARIABLES)
#define VR(vr) ((const ValueReference *)(vr))
#define EXIT "fmi3ExitInitializationMode"

typedef struct {
    fmi3InstanceEnvironment environment;
    fmi3LogMessageCallback logMessage;
} Host3;

typedef char host3_fits[sizeof(Host3) <= sizeof((Instance *)0)->host ? 1 : -1];

static void emit3(const Instance *in, Status status, const char *category, const char *message) {
    const Host3 *host = (const Host3 *)in->host;
    if (host->logMessage) host->logMessage(host->environment, (fmi3Status)status, category, message);
}

static void *zeroed(size_t n, size_t size) { return calloc(n, size); }

static Instance host3(fmi3InstanceEnvironment environment, fmi3LogMessageCallback logMessage) {
    Instance probe = {0};
    Host3 host = {environment, logMessage};
    memcpy(probe.host, &host, sizeof host);
    probe.emit = emit3;
    probe.allocate = zeroed;
    probe.release = free;
    probe.name = (char *)"?";
    return probe;
}

/* nValues must be nValueReferences, and the call allowed in this state (`allowed`); then
 * each reference is checked before the next is read (the count is the caller's word, and a
 * count past its array ends at the first entry that is wrong): a variable of `type`, or
 * `time`, which a Float64 get reads (`time_readable`) and nothing sets. 1 if the call may
 * go on to the framework: a NULL array (of references or of `values`) is the framework's
 * to name before any reference is read, as FMI 2.0's are. */
static int scalars(Instance *in, const char *call, unsigned allowed,
                   const fmi3ValueReference vr[], size_t nvr, const void *values,
                   size_t nvalues, int type, const char *type_name, int time_readable) {
    if (nvalues != nvr) {
        say(in, LK_ERROR, "%s: nValues = %zu with %zu value references: every variable of "
            MODEL_IDENTIFIER " is a scalar, nValues must equal nValueReferences", call, nvalues,
            nvr);
        return 0;
    }
    if (require(in, call, allowed)) return 0;
    if (!vr || !values) return 1;
    for (size_t i = 0; i < nvr; i++) {
        if (vr[i] != TIME_VR) {
            if (check_ref(in, call, vr[i], i, type, type_name)) return 0;
        } else if (type != T_REAL) {
            say(in, LK_ERROR, "%s: value reference %u ('time') is a Float64, not a %s", call,
                (unsigned)vr[i], type_name);
            return 0;
        } else if (!time_readable) {
            say(in, LK_ERROR, "%s: 'time' (value reference %u) is the independent variable: "
                "it cannot be set", call, (unsigned)vr[i]);
            return 0;
        }
    }
    return 1;
}

const char *fmi3GetVersion(void) { return fmi3Version; }

fmi3Instance fmi3InstantiateCoSimulation(
    fmi3String instanceName, fmi3String instantiationToken, fmi3String resourcePath,
    fmi3Boolean visible, fmi3Boolean loggingOn, fmi3Boolean eventModeUsed,
    fmi3Boolean earlyReturnAllowed, const fmi3ValueReference requiredIntermediateVariables[],
    size_t nRequiredIntermediateVariables, fmi3InstanceEnvironment instanceEnvironment,
    fmi3LogMessageCallback logMessage, fmi3IntermediateUpdateCallback intermediateUpdate) {
    (void)visible, (void)earlyReturnAllowed; /* doStep never returns early */
    (void)intermediateUpdate;                 /* providesIntermediateUpdate is false */
    Instance probe = host3(instanceEnvironment, logMessage);
    const char *call = "fmi3InstantiateCoSimulation";
    probe.event_mode_used = eventModeUsed ? 1 : 0;
    for (size_t i = 0; i < nRequiredIntermediateVariables; i++)
        if (!requiredIntermediateVariables || requiredIntermediateVariables[i] > TIME_VR ||
            (requiredIntermediateVariables[i] < TIME_VR &&
             !VARIABLES[requiredIntermediateVariables[i]].name)) {
            say(&probe, LK_ERROR, "%s: required intermediate variable (entry %zu) is not a "
                "variable of " MODEL_IDENTIFIER, call, i);
            return NULL;
        }
    return lk_instantiate(call, instanceName, instantiationToken, resourcePath, 0, loggingOn,
                          &probe);
}

fmi3Instance fmi3InstantiateModelExchange(fmi3String instanceName,
                                          fmi3String instantiationToken,
                                          fmi3String resourcePath, fmi3Boolean visible,
                                          fmi3Boolean loggingOn,
                                          fmi3InstanceEnvironment instanceEnvironment,
                                          fmi3LogMessageCallback logMessage) {
    (void)visible;
    Instance probe = host3(instanceEnvironment, logMessage);
#if N_STATES > 0
    probe.exchange = 1;
    return lk_instantiate("fmi3InstantiateModelExchange", instanceName, instantiationToken,
                          resourcePath, 0, loggingOn, &probe);
#else
    (void)instanceName, (void)instantiationToken, (void)resourcePath;
    probe.logging = loggingOn;
    say(&probe, LK_ERROR, "fmi3InstantiateModelExchange: " MODEL_IDENTIFIER
        " supports co-simulation only");
    return NULL;
#endif
}

fmi3Instance fmi3InstantiateScheduledExecution(
    fmi3String instanceName, fmi3String instantiationToken, fmi3String resourcePath,
    fmi3Boolean visible, fmi3Boolean loggingOn, fmi3InstanceEnvironment instanceEnvironment,
    fmi3LogMessageCallback logMessage, fmi3ClockUpdateCallback clockUpdate,
    fmi3LockPreemptionCallback lockPreemption, fmi3UnlockPreemptionCallback unlockPreemption) {
    (void)instanceName, (void)instantiationToken, (void)resourcePath, (void)visible;
    (void)loggingOn, (void)clockUpdate, (void)lockPreemption, (void)unlockPreemption;
    Instance probe = host3(instanceEnvironment, logMessage);
    say(&probe, LK_ERROR, "fmi3InstantiateScheduledExecution: " MODEL_IDENTIFIER
        " supports co-simulation only");
    return NULL;
}

void fmi3FreeInstance(fmi3Instance instance) { lk_free((Instance *)instance); }

fmi3Status fmi3SetDebugLogging(fmi3Instance instance, fmi3Boolean loggingOn, size_t nCategories,
                               const fmi3String categories[]) {
    return (fmi3Status)lk_set_debug_logging(instance, "fmi3SetDebugLogging", loggingOn,
                                            nCategories, categories);
}

fmi3Status fmi3EnterInitializationMode(fmi3Instance instance, fmi3Boolean toleranceDefined,
                                       fmi3Float64 tolerance, fmi3Float64 startTime,
                                       fmi3Boolean stopTimeDefined, fmi3Float64 stopTime) {
    const char *call = "fmi3EnterInitializationMode";
    Status s = lk_setup(instance, call, toleranceDefined, tolerance, startTime, stopTimeDefined,
                        stopTime);
    return (fmi3Status)(s == LK_OK ? lk_enter_initialization(instance, call) : s);
}

fmi3Status fmi3ExitInitializationMode(fmi3Instance instance) {
    return (fmi3Status)lk_exit_initialization(instance, EXIT);
}

fmi3Status fmi3Terminate(fmi3Instance instance) {
    return (fmi3Status)lk_terminate(instance, "fmi3Terminate");
}

fmi3Status fmi3Reset(fmi3Instance instance) { return (fmi3Status)lk_reset(instance, "fmi3Reset"); }

/* -- values ------------------------------------------------------------------------------ */
fmi3Status fmi3GetFloat64(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                          size_t nValueReferences, fmi3Float64 values[], size_t nValues) {
    const char *call = "fmi3GetFloat64";
    Instance *in = lk_instance(instance, call);
    if (!in) return fmi3Error;
    const fmi3ValueReference *vr = valueReferences;
    if (!scalars(in, call, READABLE, vr, nValueReferences, values, nValues, T_REAL, "Float64",
                 1))
        return fmi3Error;
    if (!vr || !values) return (fmi3Status)lk_get_real(in, call, VR(vr), nValueReferences, values);
    Status status = LK_OK;
    /* runs of the model's variables go to the framework; `time` is this adapter's */
    for (size_t i = 0; i < nValueReferences && status <= LK_WARNING;) {
        if (vr[i] == TIME_VR) {
            values[i++] = in->time;
            continue;
        }
        size_t j = i;
        while (j < nValueReferences && vr[j] != TIME_VR) j++;
        Status s = lk_get_real(in, call, VR(vr) + i, j - i, values + i);
        status = s > status ? s : status;
        i = j;
    }
    return (fmi3Status)status;
}

fmi3Status fmi3GetInt32(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                        size_t nValueReferences, fmi3Int32 values[], size_t nValues) {
    Instance *in = lk_instance(instance, "fmi3GetInt32");
    if (!in) return fmi3Error;
    if (!scalars(in, "fmi3GetInt32", READABLE, valueReferences, nValueReferences, values,
                 nValues, T_INTEGER, "Int32", 0))
        return fmi3Error;
    return (fmi3Status)lk_get_integer(in, "fmi3GetInt32", VR(valueReferences), nValueReferences,
                                      (int *)values);
}

fmi3Status fmi3GetString(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                         size_t nValueReferences, fmi3String values[], size_t nValues) {
    Instance *in = lk_instance(instance, "fmi3GetString");
    if (!in) return fmi3Error;
    if (!scalars(in, "fmi3GetString", READABLE, valueReferences, nValueReferences, values,
                 nValues, T_STRING, "String", 0))
        return fmi3Error;
    return (fmi3Status)lk_get_string(in, "fmi3GetString", VR(valueReferences), nValueReferences,
                                     values);
}

fmi3Status fmi3SetFloat64(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                          size_t nValueReferences, const fmi3Float64 values[], size_t nValues) {
    Instance *in = lk_instance(instance, "fmi3SetFloat64");
    if (!in) return fmi3Error;
    if (!scalars(in, "fmi3SetFloat64", WRITABLE, valueReferences, nValueReferences, values,
                 nValues, T_REAL, "Float64", 0))
        return fmi3Error;
    return (fmi3Status)lk_set_real(in, "fmi3SetFloat64", EXIT, VR(valueReferences),
                                   nValueReferences, values);
}

fmi3Status fmi3SetInt32(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                        size_t nValueReferences, const fmi3Int32 values[], size_t nValues) {
    Instance *in = lk_instance(instance, "fmi3SetInt32");
    if (!in) return fmi3Error;
    if (!scalars(in, "fmi3SetInt32", WRITABLE, valueReferences, nValueReferences, values,
                 nValues, T_INTEGER, "Int32", 0))
        return fmi3Error;
    return (fmi3Status)lk_set_integer(in, "fmi3SetInt32", EXIT, VR(valueReferences),
                                      nValueReferences, (const int *)values);
}

fmi3Status fmi3SetString(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                         size_t nValueReferences, const fmi3String values[], size_t nValues) {
    Instance *in = lk_instance(instance, "fmi3SetString");
    if (!in) return fmi3Error;
    if (!scalars(in, "fmi3SetString", WRITABLE, valueReferences, nValueReferences, values,
                 nValues, T_STRING, "String", 0))
        return fmi3Error;
    return (fmi3Status)lk_set_string(in, "fmi3SetString", EXIT, VR(valueReferences),
                                     nValueReferences, values);
}

/* The types this model has no variables of: a call with references is a wrong type (or an
 * unknown reference), named as such; an empty call is fmi3OK in a state that allows it. */
#define NO_VARIABLES(Name, ctype, allowed)                                                 \
    fmi3Status fmi3##Name(fmi3Instance instance, const fmi3ValueReference valueReferences[], \
                          size_t nValueReferences, ctype values[], size_t nValues) {       \
        Instance *in = lk_instance(instance, "fmi3" #Name);                                \
        if (!in) return fmi3Error;                                                         \
        if (!scalars(in, "fmi3" #Name, allowed, valueReferences, nValueReferences, values,     \
                     nValues, -1, #Name + 3, 0))                                           \
            return fmi3Error;                                                              \
        return (fmi3Status)lk_no_variables(in, "fmi3" #Name, allowed, VR(valueReferences), \
                                           nValueReferences, values, #Name + 3);           \
    }
NO_VARIABLES(GetFloat32, fmi3Float32, READABLE)
NO_VARIABLES(GetInt8, fmi3Int8, READABLE)
NO_VARIABLES(GetUInt8, fmi3UInt8, READABLE)
NO_VARIABLES(GetInt16, fmi3Int16, READABLE)
NO_VARIABLES(GetUInt16, fmi3UInt16, READABLE)
NO_VARIABLES(GetUInt32, fmi3UInt32, READABLE)
NO_VARIABLES(GetInt64, fmi3Int64, READABLE)
NO_VARIABLES(GetUInt64, fmi3UInt64, READABLE)
NO_VARIABLES(GetBoolean, fmi3Boolean, READABLE)
NO_VARIABLES(SetFloat32, const fmi3Float32, WRITABLE)
NO_VARIABLES(SetInt8, const fmi3Int8, WRITABLE)
NO_VARIABLES(SetUInt8, const fmi3UInt8, WRITABLE)
NO_VARIABLES(SetInt16, const fmi3Int16, WRITABLE)
NO_VARIABLES(SetUInt16, const fmi3UInt16, WRITABLE)
NO_VARIABLES(SetUInt32, const fmi3UInt32, WRITABLE)
NO_VARIABLES(SetInt64, const fmi3Int64, WRITABLE)
NO_VARIABLES(SetUInt64, const fmi3UInt64, WRITABLE)
NO_VARIABLES(SetBoolean, const fmi3Boolean, WRITABLE)

fmi3Status fmi3GetBinary(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                         size_t nValueReferences, size_t valueSizes[], fmi3Binary values[],
                         size_t nValues) {
    Instance *in = lk_instance(instance, "fmi3GetBinary");
    if (!in) return fmi3Error;
    if (nValueReferences && !valueSizes)
        return (fmi3Status)say(in, LK_ERROR, "fmi3GetBinary: valueSizes is NULL");
    if (!scalars(in, "fmi3GetBinary", READABLE, valueReferences, nValueReferences, values,
                 nValues, -1, "Binary", 0))
        return fmi3Error;
    return (fmi3Status)lk_no_variables(in, "fmi3GetBinary", READABLE, VR(valueReferences),
                                       nValueReferences, values, "Binary");
}

fmi3Status fmi3SetBinary(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                         size_t nValueReferences, const size_t valueSizes[],
                         const fmi3Binary values[], size_t nValues) {
    Instance *in = lk_instance(instance, "fmi3SetBinary");
    if (!in) return fmi3Error;
    if (nValueReferences && !valueSizes)
        return (fmi3Status)say(in, LK_ERROR, "fmi3SetBinary: valueSizes is NULL");
    if (!scalars(in, "fmi3SetBinary", WRITABLE, valueReferences, nValueReferences, values,
                 nValues, -1, "Binary", 0))
        return fmi3Error;
    return (fmi3Status)lk_no_variables(in, "fmi3SetBinary", WRITABLE, VR(valueReferences),
                                       nValueReferences, values, "Binary");
}

fmi3Status fmi3GetClock(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                        size_t nValueReferences, fmi3Clock values[]) {
    return (fmi3Status)lk_no_variables(instance, "fmi3GetClock", READABLE, VR(valueReferences),
                                       nValueReferences, values, "Clock");
}

fmi3Status fmi3SetClock(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                        size_t nValueReferences, const fmi3Clock values[]) {
    return (fmi3Status)lk_no_variables(instance, "fmi3SetClock", WRITABLE, VR(valueReferences),
                                       nValueReferences, values, "Clock");
}

/* -- stepping ---------------------------------------------------------------------------- */
fmi3Status fmi3DoStep(fmi3Instance instance, fmi3Float64 currentCommunicationPoint,
                      fmi3Float64 communicationStepSize,
                      fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                      fmi3Boolean *eventHandlingNeeded, fmi3Boolean *terminateSimulation,
                      fmi3Boolean *earlyReturn, fmi3Float64 *lastSuccessfulTime) {
    Instance *in = lk_instance(instance, "fmi3DoStep");
    if (!in) return fmi3Error;
    (void)noSetFMUStatePriorToCurrentPoint;
    if (!eventHandlingNeeded || !terminateSimulation || !earlyReturn || !lastSuccessfulTime)
        return (fmi3Status)say(in, LK_ERROR, "fmi3DoStep: %s is NULL",
                               !eventHandlingNeeded ? "eventHandlingNeeded"
                               : !terminateSimulation ? "terminateSimulation"
                               : !earlyReturn ? "earlyReturn" : "lastSuccessfulTime");
    Status s = lk_do_step(in, "fmi3DoStep", currentCommunicationPoint, communicationStepSize);
    *eventHandlingNeeded = fmi3False;
    *earlyReturn = fmi3False;
    /* a discarded step asks to end the run (a master that retried the same inputs would
     * retry for ever); a later valid step is still taken */
    *terminateSimulation = s == LK_DISCARD ? fmi3True : fmi3False;
    *lastSuccessfulTime = in->time;
    return (fmi3Status)s;
}

/* -- FMU states -------------------------------------------------------------------------- */
fmi3Status fmi3GetFMUState(fmi3Instance instance, fmi3FMUState *state) {
    return (fmi3Status)lk_get_state(instance, "fmi3GetFMUState", state);
}

fmi3Status fmi3SetFMUState(fmi3Instance instance, fmi3FMUState state) {
    return (fmi3Status)lk_set_state(instance, "fmi3SetFMUState", state);
}

fmi3Status fmi3FreeFMUState(fmi3Instance instance, fmi3FMUState *state) {
    return (fmi3Status)lk_free_state(instance, "fmi3FreeFMUState", state);
}

fmi3Status fmi3SerializedFMUStateSize(fmi3Instance instance, fmi3FMUState state, size_t *size) {
    return (fmi3Status)lk_state_size(instance, "fmi3SerializedFMUStateSize", state, size);
}

fmi3Status fmi3SerializeFMUState(fmi3Instance instance, fmi3FMUState state,
                                 fmi3Byte serializedState[], size_t size) {
    return (fmi3Status)lk_serialize(instance, "fmi3SerializeFMUState", state, serializedState,
                                    size);
}

fmi3Status fmi3DeserializeFMUState(fmi3Instance instance, const fmi3Byte serializedState[],
                                   size_t size, fmi3FMUState *state) {
    return (fmi3Status)lk_deserialize(instance, "fmi3DeserializeFMUState", serializedState, size,
                                      state);
}

/* -- not supported: every other FMI 3.0 function answers fmi3Error with a log ------------- */
#define UNSUPPORTED(name, why) return (fmi3Status)lk_refuse(instance, #name, why)

/* -- event mode: co-simulation has no events; an importer that uses event mode may enter it */
fmi3Status fmi3EnterEventMode(fmi3Instance instance) {
    Instance *in = lk_instance(instance, "fmi3EnterEventMode");
    if (!in) return fmi3Error;
#if N_STATES > 0
    if (in->exchange) return (fmi3Status)lk_exchange_event_mode(in, "fmi3EnterEventMode");
#endif
    return (fmi3Status)lk_enter_event_mode(in, "fmi3EnterEventMode");
}

fmi3Status fmi3EnterStepMode(fmi3Instance instance) {
    return (fmi3Status)lk_enter_step_mode(instance, "fmi3EnterStepMode");
}

fmi3Status fmi3UpdateDiscreteStates(fmi3Instance instance, fmi3Boolean *discreteStatesNeedUpdate,
                                    fmi3Boolean *terminateSimulation,
                                    fmi3Boolean *nominalsOfContinuousStatesChanged,
                                    fmi3Boolean *valuesOfContinuousStatesChanged,
                                    fmi3Boolean *nextEventTimeDefined,
                                    fmi3Float64 *nextEventTime) {
    fmi3Boolean *flags[] = {discreteStatesNeedUpdate, terminateSimulation,
                            nominalsOfContinuousStatesChanged, valuesOfContinuousStatesChanged,
                            nextEventTimeDefined};
    Instance *in = lk_instance(instance, "fmi3UpdateDiscreteStates");
    if (!in) return fmi3Error;
    for (size_t k = 0; k < sizeof flags / sizeof *flags; k++)
        if (!flags[k])
            return (fmi3Status)say(in, LK_ERROR, "fmi3UpdateDiscreteStates: argument %zu is NULL",
                                   k + 2);
    if (!nextEventTime)
        return (fmi3Status)say(in, LK_ERROR, "fmi3UpdateDiscreteStates: nextEventTime is NULL");
    int moved;
    Status s = lk_update_discrete_states(in, "fmi3UpdateDiscreteStates", &moved);
    if (s != LK_OK) return (fmi3Status)s;
    for (size_t k = 0; k < sizeof flags / sizeof *flags; k++) *flags[k] = fmi3False;
    *valuesOfContinuousStatesChanged = moved ? fmi3True : fmi3False;
    *nextEventTime = 0.0;
    return fmi3OK;
}

/* -- the ModelStructure's dependencies, from config.h's table -------------------------------- */
fmi3Status fmi3GetNumberOfVariableDependencies(fmi3Instance instance,
                                               fmi3ValueReference valueReference,
                                               size_t *nDependencies) {
    const char *call = "fmi3GetNumberOfVariableDependencies";
    Instance *in = lk_instance(instance, call);
    if (!in) return fmi3Error;
    if (!nDependencies) return (fmi3Status)say(in, LK_ERROR, "%s: nDependencies is NULL", call);
    const ValueReference *list;
    *nDependencies = 0; /* `time` depends on nothing */
    if (valueReference == TIME_VR) return fmi3OK;
    return (fmi3Status)lk_dependencies(in, call, valueReference, &list, nDependencies);
}

fmi3Status fmi3GetVariableDependencies(fmi3Instance instance, fmi3ValueReference dependent,
                                       size_t elementIndicesOfDependent[],
                                       fmi3ValueReference independents[],
                                       size_t elementIndicesOfIndependents[],
                                       fmi3DependencyKind dependencyKinds[],
                                       size_t nDependencies) {
    const char *call = "fmi3GetVariableDependencies";
    Instance *in = lk_instance(instance, call);
    if (!in) return fmi3Error;
    const ValueReference *list = NULL;
    size_t n = 0;
    if (dependent != TIME_VR && lk_dependencies(in, call, dependent, &list, &n) != LK_OK)
        return fmi3Error;
    if (nDependencies != n)
        return (fmi3Status)say(in, LK_ERROR, "%s: nDependencies = %zu, but value reference %u "
                               "has %zu dependencies now", call, nDependencies,
                               (unsigned)dependent, n);
    if (n && (!elementIndicesOfDependent || !independents || !elementIndicesOfIndependents ||
              !dependencyKinds))
        return (fmi3Status)say(in, LK_ERROR, "%s: a result array is NULL", call);
    for (size_t k = 0; k < n; k++) { /* scalars: element 0, the whole variable */
        elementIndicesOfDependent[k] = 0;
        independents[k] = list[k];
        elementIndicesOfIndependents[k] = 0;
        dependencyKinds[k] = fmi3Dependent;
    }
    return fmi3OK;
}

fmi3Status fmi3GetDirectionalDerivative(fmi3Instance instance,
                                        const fmi3ValueReference unknowns[], size_t nUnknowns,
                                        const fmi3ValueReference knowns[], size_t nKnowns,
                                        const fmi3Float64 seed[], size_t nSeed,
                                        fmi3Float64 sensitivity[], size_t nSensitivity) {
    return (fmi3Status)lk_directional(instance, "fmi3GetDirectionalDerivative", VR(unknowns),
                                      nUnknowns, VR(knowns), nKnowns, seed, nSeed, sensitivity,
                                      nSensitivity);
}

fmi3Status fmi3GetAdjointDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[],
                                    size_t nUnknowns, const fmi3ValueReference knowns[],
                                    size_t nKnowns, const fmi3Float64 seed[], size_t nSeed,
                                    fmi3Float64 sensitivity[], size_t nSensitivity) {
    (void)unknowns, (void)nUnknowns, (void)knowns, (void)nKnowns, (void)seed, (void)nSeed;
    (void)sensitivity, (void)nSensitivity;
    UNSUPPORTED(fmi3GetAdjointDerivative, "providesAdjointDerivatives is false");
}

fmi3Status fmi3EnterConfigurationMode(fmi3Instance instance) {
    UNSUPPORTED(fmi3EnterConfigurationMode, MODEL_IDENTIFIER " has no structural parameters");
}

fmi3Status fmi3ExitConfigurationMode(fmi3Instance instance) {
    UNSUPPORTED(fmi3ExitConfigurationMode, MODEL_IDENTIFIER " has no structural parameters");
}

#define NO_CLOCKS "no clocks"
fmi3Status fmi3GetIntervalDecimal(fmi3Instance instance,
                                  const fmi3ValueReference valueReferences[],
                                  size_t nValueReferences, fmi3Float64 intervals[],
                                  fmi3IntervalQualifier qualifiers[]) {
    (void)valueReferences, (void)nValueReferences, (void)intervals, (void)qualifiers;
    UNSUPPORTED(fmi3GetIntervalDecimal, NO_CLOCKS);
}

fmi3Status fmi3GetIntervalFraction(fmi3Instance instance,
                                   const fmi3ValueReference valueReferences[],
                                   size_t nValueReferences, fmi3UInt64 counters[],
                                   fmi3UInt64 resolutions[], fmi3IntervalQualifier qualifiers[]) {
    (void)valueReferences, (void)nValueReferences, (void)counters, (void)resolutions;
    (void)qualifiers;
    UNSUPPORTED(fmi3GetIntervalFraction, NO_CLOCKS);
}

fmi3Status fmi3GetShiftDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                               size_t nValueReferences, fmi3Float64 shifts[]) {
    (void)valueReferences, (void)nValueReferences, (void)shifts;
    UNSUPPORTED(fmi3GetShiftDecimal, NO_CLOCKS);
}

fmi3Status fmi3GetShiftFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                size_t nValueReferences, fmi3UInt64 counters[],
                                fmi3UInt64 resolutions[]) {
    (void)valueReferences, (void)nValueReferences, (void)counters, (void)resolutions;
    UNSUPPORTED(fmi3GetShiftFraction, NO_CLOCKS);
}

fmi3Status fmi3SetIntervalDecimal(fmi3Instance instance,
                                  const fmi3ValueReference valueReferences[],
                                  size_t nValueReferences, const fmi3Float64 intervals[]) {
    (void)valueReferences, (void)nValueReferences, (void)intervals;
    UNSUPPORTED(fmi3SetIntervalDecimal, NO_CLOCKS);
}

fmi3Status fmi3SetIntervalFraction(fmi3Instance instance,
                                   const fmi3ValueReference valueReferences[],
                                   size_t nValueReferences, const fmi3UInt64 counters[],
                                   const fmi3UInt64 resolutions[]) {
    (void)valueReferences, (void)nValueReferences, (void)counters, (void)resolutions;
    UNSUPPORTED(fmi3SetIntervalFraction, NO_CLOCKS);
}

fmi3Status fmi3SetShiftDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                               size_t nValueReferences, const fmi3Float64 shifts[]) {
    (void)valueReferences, (void)nValueReferences, (void)shifts;
    UNSUPPORTED(fmi3SetShiftDecimal, NO_CLOCKS);
}

fmi3Status fmi3SetShiftFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                size_t nValueReferences, const fmi3UInt64 counters[],
                                const fmi3UInt64 resolutions[]) {
    (void)valueReferences, (void)nValueReferences, (void)counters, (void)resolutions;
    UNSUPPORTED(fmi3SetShiftFraction, NO_CLOCKS);
}

fmi3Status fmi3EvaluateDiscreteStates(fmi3Instance instance) {
    UNSUPPORTED(fmi3EvaluateDiscreteStates, "providesEvaluateDiscreteStates is false");
}

#if N_STATES > 0
/* -- model exchange ------------------------------------------------------------------------ */
fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance instance) {
    return (fmi3Status)lk_enter_continuous_time_mode(instance, "fmi3EnterContinuousTimeMode");
}

fmi3Status fmi3CompletedIntegratorStep(fmi3Instance instance,
                                       fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi3Boolean *enterEventMode,
                                       fmi3Boolean *terminateSimulation) {
    (void)noSetFMUStatePriorToCurrentPoint;
    Instance *in = lk_instance(instance, "fmi3CompletedIntegratorStep");
    if (!in) return fmi3Error;
    if (!enterEventMode || !terminateSimulation)
        return (fmi3Status)say(in, LK_ERROR, "fmi3CompletedIntegratorStep: %s is NULL",
                               !enterEventMode ? "enterEventMode" : "terminateSimulation");
    Status s = lk_completed_integrator_step(in, "fmi3CompletedIntegratorStep");
    if (s == LK_OK) *enterEventMode = *terminateSimulation = fmi3False;
    return (fmi3Status)s;
}

fmi3Status fmi3SetTime(fmi3Instance instance, fmi3Float64 time) {
    return (fmi3Status)lk_set_time(instance, "fmi3SetTime", time);
}

fmi3Status fmi3SetContinuousStates(fmi3Instance instance, const fmi3Float64 continuousStates[],
                                   size_t nContinuousStates) {
    return (fmi3Status)lk_set_continuous_states(instance, "fmi3SetContinuousStates",
                                                continuousStates, nContinuousStates);
}

fmi3Status fmi3GetContinuousStateDerivatives(fmi3Instance instance, fmi3Float64 derivatives[],
                                             size_t nContinuousStates) {
    return (fmi3Status)lk_get_derivatives(instance, "fmi3GetContinuousStateDerivatives",
                                          derivatives, nContinuousStates);
}

fmi3Status fmi3GetEventIndicators(fmi3Instance instance, fmi3Float64 eventIndicators[],
                                  size_t nEventIndicators) {
    return (fmi3Status)lk_get_event_indicators(instance, "fmi3GetEventIndicators",
                                               eventIndicators, nEventIndicators);
}

fmi3Status fmi3GetContinuousStates(fmi3Instance instance, fmi3Float64 continuousStates[],
                                   size_t nContinuousStates) {
    return (fmi3Status)lk_get_continuous_states(instance, "fmi3GetContinuousStates",
                                                continuousStates, nContinuousStates);
}

fmi3Status fmi3GetNominalsOfContinuousStates(fmi3Instance instance, fmi3Float64 nominals[],
                                             size_t nContinuousStates) {
    return (fmi3Status)lk_get_nominals(instance, "fmi3GetNominalsOfContinuousStates", nominals,
                                       nContinuousStates);
}

fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance instance, size_t *nEventIndicators) {
    Instance *in = lk_instance(instance, "fmi3GetNumberOfEventIndicators");
    if (!in) return fmi3Error;
    if (!nEventIndicators)
        return (fmi3Status)say(in, LK_ERROR, "fmi3GetNumberOfEventIndicators: the pointer is NULL");
    *nEventIndicators = N_EVENTS;
    return fmi3OK;
}

fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance instance, size_t *nContinuousStates) {
    Instance *in = lk_instance(instance, "fmi3GetNumberOfContinuousStates");
    if (!in) return fmi3Error;
    if (!nContinuousStates)
        return (fmi3Status)say(in, LK_ERROR, "fmi3GetNumberOfContinuousStates: the pointer is "
                               "NULL");
    *nContinuousStates = N_STATES;
    return fmi3OK;
}
#else
#define CS_ONLY "model exchange: " MODEL_IDENTIFIER " supports co-simulation only"
fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance instance) {
    UNSUPPORTED(fmi3EnterContinuousTimeMode, CS_ONLY);
}

fmi3Status fmi3CompletedIntegratorStep(fmi3Instance instance,
                                       fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi3Boolean *enterEventMode,
                                       fmi3Boolean *terminateSimulation) {
    (void)noSetFMUStatePriorToCurrentPoint, (void)enterEventMode, (void)terminateSimulation;
    UNSUPPORTED(fmi3CompletedIntegratorStep, CS_ONLY);
}

fmi3Status fmi3SetTime(fmi3Instance instance, fmi3Float64 time) {
    (void)time;
    UNSUPPORTED(fmi3SetTime, CS_ONLY);
}

fmi3Status fmi3SetContinuousStates(fmi3Instance instance, const fmi3Float64 continuousStates[],
                                   size_t nContinuousStates) {
    (void)continuousStates, (void)nContinuousStates;
    UNSUPPORTED(fmi3SetContinuousStates, CS_ONLY);
}

fmi3Status fmi3GetContinuousStateDerivatives(fmi3Instance instance, fmi3Float64 derivatives[],
                                             size_t nContinuousStates) {
    (void)derivatives, (void)nContinuousStates;
    UNSUPPORTED(fmi3GetContinuousStateDerivatives, CS_ONLY);
}

fmi3Status fmi3GetEventIndicators(fmi3Instance instance, fmi3Float64 eventIndicators[],
                                  size_t nEventIndicators) {
    (void)eventIndicators, (void)nEventIndicators;
    UNSUPPORTED(fmi3GetEventIndicators, CS_ONLY);
}

fmi3Status fmi3GetContinuousStates(fmi3Instance instance, fmi3Float64 continuousStates[],
                                   size_t nContinuousStates) {
    (void)continuousStates, (void)nContinuousStates;
    UNSUPPORTED(fmi3GetContinuousStates, CS_ONLY);
}

fmi3Status fmi3GetNominalsOfContinuousStates(fmi3Instance instance, fmi3Float64 nominals[],
                                             size_t nContinuousStates) {
    (void)nominals, (void)nContinuousStates;
    UNSUPPORTED(fmi3GetNominalsOfContinuousStates, CS_ONLY);
}

fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance instance, size_t *nEventIndicators) {
    (void)nEventIndicators;
    UNSUPPORTED(fmi3GetNumberOfEventIndicators, CS_ONLY);
}

fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance instance, size_t *nContinuousStates) {
    (void)nContinuousStates;
    UNSUPPORTED(fmi3GetNumberOfContinuousStates, CS_ONLY);
}

#endif

fmi3Status fmi3GetOutputDerivatives(fmi3Instance instance,
                                    const fmi3ValueReference valueReferences[],
                                    size_t nValueReferences, const fmi3Int32 orders[],
                                    fmi3Float64 values[], size_t nValues) {
    (void)valueReferences, (void)nValueReferences, (void)orders, (void)values, (void)nValues;
    UNSUPPORTED(fmi3GetOutputDerivatives, "maxOutputDerivativeOrder is 0");
}

fmi3Status fmi3ActivateModelPartition(fmi3Instance instance, fmi3ValueReference clockReference,
                                      fmi3Float64 activationTime) {
    (void)clockReference, (void)activationTime;
    UNSUPPORTED(fmi3ActivateModelPartition, "scheduled execution: " MODEL_IDENTIFIER
                " supports co-simulation only");
}
