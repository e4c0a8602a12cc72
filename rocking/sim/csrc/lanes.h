/* The C batch in lanes (lanes.c): several runs of rocking_simulate_batch integrated in lockstep, the stages
 * of their rocking steps computed over vectors, one run per element.
 *
 * Each run is the scalar phase machine of sim.c itself, on a stack of its own (a coroutine): events, phase
 * changes, impacts, verdicts and the step-size control are the scalar code, case by case. Only the six
 * stages and the error estimate of a step without a vertical component and without slip, rocking or in full
 * contact (the right-hand sides ODE_*_ROCKING, ODE_*_CONTACT), and the power of that error the step-size
 * control takes, are computed over vectors: every element goes
 * through the operations of the scalar stages, in their order, except sin and cos (of theta, of a one-sine
 * pulse) and that power, which lanes.c computes with its own vector functions (a few units in the last place
 * from libm's). The results then differ from the scalar path's by the last bits of those values, carried
 * along the run (tests/test_lanes.py bounds the difference). Every other step (a slide, a vertical component,
 * full contact of a model whose contact accelerations are not straight-line) is the scalar step, in place.
 *
 * When the batch runs scalar instead (rocking_simulate_batch_lanes with lanes = 0, or rocking_lanes() = 0):
 *   - the environment variable ROCKING_LANES is "0";
 *   - the machine is not x86-64 with ELF objects (Linux, the BSDs: the coroutines switch stacks with a few
 *     lines of System V x86-64 assembly);
 *   - the model's rocking accelerations are not straight-line arithmetic with sin and cos alone
 *     (rocking/sim/lanes_rhs.py; e.g. a Hunt-Crossley pad's pow);
 *   - the stacks of the coroutines cannot be allocated.
 * The width follows the CPU: AVX2's 4 doubles per vector, else SSE2's 2; the environment variable
 * ROCKING_LANES_ISA = "sse2" caps it (to measure a narrower machine), "avx512" allows AVX-512F's 8 (lanes.c's
 * lanes_width says why they are not the default).
 */
#ifndef ROCKING_LANES_H
#define ROCKING_LANES_H

#include <stdint.h>

#include "sim.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The doubles per vector a batch run now would use: 8, 4 or 2; 0 when it would run scalar (above). */
int rocking_lanes(void);

/* rocking_simulate_batch with the lanes (on != 0, where rocking_lanes() > 0) or scalar (on = 0): the scalar
 * path is then bit for bit that of rocking_simulate for each case. rocking_simulate_batch is on = 1. */
void rocking_simulate_batch_lanes(int64_t n, const double *p, const rocking_case *cases, rocking_result *out,
                                  const rocking_control *control, int32_t on);

#ifdef __cplusplus
}
#endif

#endif
