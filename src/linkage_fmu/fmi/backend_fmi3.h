/* The backend interface of fmi2.c in FMI 3.0 terms, for fmi3.c.
 *
 * A backend (backend_native.c) is written against fmi2.c's interface: its functions
 * take and answer FMI 2.0 types and status codes. fmi3.c includes this header before
 * BACKEND so that the same backend compiles, unchanged, behind the FMI 3.0 framework:
 *
 * - fmi2Status is fmi3Status: OK, Warning, Discard, Error, Fatal have the same values
 *   (0..4) in both standards; FMI 3.0 has no Pending (fmi3.c never receives it);
 * - fmi2Real is fmi3Float64, fmi2Integer fmi3Int32 (both int on every platform the FMU
 *   is built for), fmi2String fmi3String, fmi2ValueReference fmi3ValueReference;
 * - fmi2Boolean is fmi3Boolean, a C bool (an int in FMI 2.0): the backend only passes
 *   booleans along and compares them with fmi2True/fmi2False;
 * - the calls the backend names in its logs are FMI 3.0's (CALL_*).
 */
#ifndef BACKEND_FMI3_H
#define BACKEND_FMI3_H

#include "fmi3FunctionTypes.h"

typedef fmi3Status fmi2Status;
#define fmi2OK fmi3OK
#define fmi2Warning fmi3Warning
#define fmi2Discard fmi3Discard
#define fmi2Error fmi3Error
#define fmi2Fatal fmi3Fatal

typedef fmi3ValueReference fmi2ValueReference;
typedef fmi3Float64 fmi2Real;
typedef fmi3Int32 fmi2Integer;
typedef fmi3String fmi2String;
typedef fmi3Boolean fmi2Boolean;
#define fmi2True fmi3True
#define fmi2False fmi3False

/* the same status codes, whichever standard's names a backend uses */
typedef char fmi2_status_values_match[(fmi3OK == 0 && fmi3Warning == 1 && fmi3Discard == 2 &&
                                       fmi3Error == 3 && fmi3Fatal == 4) ? 1 : -1];

#define CALL_INSTANTIATE "fmi3InstantiateCoSimulation"
#define CALL_EXIT_INITIALIZATION "fmi3ExitInitializationMode"
#define CALL_GET_REAL "fmi3GetFloat64"
#define CALL_SET_REAL "fmi3SetFloat64"
#define CALL_SET_INTEGER "fmi3SetInt32"
#define CALL_SET_STRING "fmi3SetString"
#define CALL_DO_STEP "fmi3DoStep"
#define CALL_GET_STATE "fmi3GetFMUState"
#define CALL_DESERIALIZE "fmi3DeserializeFMUState"

#endif
