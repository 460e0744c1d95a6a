/* The Linux binary of a musclesim FMI 3.0 FMU: as fmi2_loader.c for FMI 2.0, starts the Python
 * interpreter the FMU was built with when the host process has none, then loads pythonfmu3's
 * binary (beside this one) and forwards every FMI 3.0 call to it unchanged.
 *
 * The instantiation functions (they start Python first), fmi3FreeInstance (it counts instances)
 * and fmi3GetVersion are written out; the 70 others, each called with an instance, jump to
 * pythonfmu3's function with the caller's arguments untouched (x86-64: the binary's platform,
 * x86_64-linux), so that no signature is written twice.
 *
 * musclesim.cosim.loader compiles this file with loader_config.h (see loader_core.h).
 */
#include "loader_core.h"

#include "fmi3Functions.h"

#if !defined(__x86_64__)
#error "the FMI 3.0 loader forwards calls by x86-64 jumps"
#endif

#define WRITTEN_OUT(X) \
    X(InstantiateCoSimulation) X(InstantiateModelExchange) X(InstantiateScheduledExecution) \
    X(FreeInstance)
#define DECLARE(name) static fmi3##name##TYPE *real_##name;
WRITTEN_OUT(DECLARE)

#define JUMPED(X) \
    X(ActivateModelPartition) X(CompletedIntegratorStep) X(DeserializeFMUState) X(DoStep) \
    X(EnterConfigurationMode) X(EnterContinuousTimeMode) X(EnterEventMode) \
    X(EnterInitializationMode) X(EnterStepMode) X(EvaluateDiscreteStates) \
    X(ExitConfigurationMode) X(ExitInitializationMode) X(FreeFMUState) X(GetAdjointDerivative) \
    X(GetBinary) X(GetBoolean) X(GetClock) X(GetContinuousStateDerivatives) \
    X(GetContinuousStates) X(GetDirectionalDerivative) X(GetEventIndicators) X(GetFMUState) \
    X(GetFloat32) X(GetFloat64) X(GetInt16) X(GetInt32) X(GetInt64) X(GetInt8) \
    X(GetIntervalDecimal) X(GetIntervalFraction) X(GetNominalsOfContinuousStates) \
    X(GetNumberOfContinuousStates) X(GetNumberOfEventIndicators) \
    X(GetNumberOfVariableDependencies) X(GetOutputDerivatives) X(GetShiftDecimal) \
    X(GetShiftFraction) X(GetString) X(GetUInt16) X(GetUInt32) X(GetUInt64) X(GetUInt8) \
    X(GetVariableDependencies) X(Reset) X(SerializeFMUState) X(SerializedFMUStateSize) \
    X(SetBinary) X(SetBoolean) X(SetClock) X(SetContinuousStates) X(SetDebugLogging) \
    X(SetFMUState) X(SetFloat32) X(SetFloat64) X(SetInt16) X(SetInt32) X(SetInt64) X(SetInt8) \
    X(SetIntervalDecimal) X(SetIntervalFraction) X(SetShiftDecimal) X(SetShiftFraction) \
    X(SetString) X(SetTime) X(SetUInt16) X(SetUInt32) X(SetUInt64) X(SetUInt8) X(Terminate) \
    X(UpdateDiscreteStates)

/* fmi3<name>: jump to pythonfmu3's function (a pointer the linker resolves within this binary) */
#define JUMP(name) \
    __attribute__((visibility("hidden"))) void *jump_##name; \
    __asm__(".text\n.globl fmi3" #name "\n.type fmi3" #name ", @function\nfmi3" #name ":\n" \
            "    endbr64\n    jmp *jump_" #name "(%rip)\n.size fmi3" #name ", .-fmi3" #name "\n");
JUMPED(JUMP)

static int resolve_real(void *lib, const char *path)
{
#define RESOLVE(name) if (!FIND(real_##name, lib, path, "fmi3" #name)) return -1;
#define RESOLVE_JUMP(name) if (!FIND(jump_##name, lib, path, "fmi3" #name)) return -1;
    WRITTEN_OUT(RESOLVE)
    JUMPED(RESOLVE_JUMP)
    return 0;
}

const char *fmi3GetVersion(void) { return fmi3Version; }

/* Start Python and load pythonfmu3's binary, or tell the host why not; 1 when ready. */
static int ready_or_say(fmi3String instanceName, fmi3InstanceEnvironment env,
                        fmi3LogMessageCallback logMessage)
{
    if (ready())
        return 1;
    if (logMessage != NULL)
        logMessage(env, fmi3Error, "logStatusError", failure);
    else
        fprintf(stderr, "%s: %s\n", instanceName ? instanceName : "FMU", failure);
    return 0;
}

static fmi3Instance counted(fmi3Instance instance)
{
    if (instance != NULL)
        count_instance(1);
    return instance;
}

fmi3Instance fmi3InstantiateCoSimulation(
    fmi3String instanceName, fmi3String instantiationToken, fmi3String resourcePath,
    fmi3Boolean visible, fmi3Boolean loggingOn, fmi3Boolean eventModeUsed,
    fmi3Boolean earlyReturnAllowed, const fmi3ValueReference requiredIntermediateVariables[],
    size_t nRequiredIntermediateVariables, fmi3InstanceEnvironment instanceEnvironment,
    fmi3LogMessageCallback logMessage, fmi3IntermediateUpdateCallback intermediateUpdate)
{
    if (!ready_or_say(instanceName, instanceEnvironment, logMessage))
        return NULL;
    return counted(real_InstantiateCoSimulation(
        instanceName, instantiationToken, resourcePath, visible, loggingOn, eventModeUsed,
        earlyReturnAllowed, requiredIntermediateVariables, nRequiredIntermediateVariables,
        instanceEnvironment, logMessage, intermediateUpdate));
}

fmi3Instance fmi3InstantiateModelExchange(
    fmi3String instanceName, fmi3String instantiationToken, fmi3String resourcePath,
    fmi3Boolean visible, fmi3Boolean loggingOn, fmi3InstanceEnvironment instanceEnvironment,
    fmi3LogMessageCallback logMessage)
{
    if (!ready_or_say(instanceName, instanceEnvironment, logMessage))
        return NULL;
    return counted(real_InstantiateModelExchange(instanceName, instantiationToken, resourcePath,
                                                 visible, loggingOn, instanceEnvironment,
                                                 logMessage));
}

fmi3Instance fmi3InstantiateScheduledExecution(
    fmi3String instanceName, fmi3String instantiationToken, fmi3String resourcePath,
    fmi3Boolean visible, fmi3Boolean loggingOn, fmi3InstanceEnvironment instanceEnvironment,
    fmi3LogMessageCallback logMessage, fmi3ClockUpdateCallback clockUpdate,
    fmi3LockPreemptionCallback lockPreemption, fmi3UnlockPreemptionCallback unlockPreemption)
{
    if (!ready_or_say(instanceName, instanceEnvironment, logMessage))
        return NULL;
    return counted(real_InstantiateScheduledExecution(
        instanceName, instantiationToken, resourcePath, visible, loggingOn, instanceEnvironment,
        logMessage, clockUpdate, lockPreemption, unlockPreemption));
}

void fmi3FreeInstance(fmi3Instance instance)
{
    if (instance == NULL)
        return;
    real_FreeInstance(instance);
    count_instance(0);
}
