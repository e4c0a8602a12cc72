/* The C simulation back end of rocking: the phase machine of docs/simulation.md
 * on a hand-written Dormand-Prince 5(4) integrator.
 *
 * sim.c knows no model: it is compiled together with one generated model and
 * uses only its generic names (MODEL_NQ, MODEL_NY, MODEL_NP, MODEL_NK, MODEL_NSTOPS,
 * model_prepare and the prepared forms of model_rocking_accel, model_contact_accel,
 * model_uplift, model_impact, model_energy, model_uplift_energy, model_critical_angle,
 * model_critical_tangent, model_mass_matrix, model_stop_gaps, model_stop_forces).
 * Build, e.g. for the model "omd":
 *
 *     cc -std=c99 -O2 -fPIC -shared -I rocking/csrc -I generated/omd \
 *        -DROCKING_MODEL_HEADER='"omd.h"' rocking/csrc/sim.c generated/omd/omd.c -lm
 *
 * (or `-DROCKING_GENERIC_NAMES -include omd.h` instead of ROCKING_MODEL_HEADER).
 * rocking/cbuild.py does this and caches the library.
 *
 * This header itself does not depend on the model: the sizes of the arrays
 * below are those of the model the library was built with, which
 * rocking_model_ny() and friends report.
 *
 * Every entry point is a pure function of its arguments (the stop flag of
 * rocking_control, which the caller owns, included): no global state, no
 * allocation, safe to call from several threads at once.
 */
#ifndef ROCKING_SIM_H
#define ROCKING_SIM_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The fields of rocking_case and rocking_result, the status and phase codes,
 * the shared constants and ROCKING_SIM_API_VERSION: generated from the tables
 * of rocking/sim/boundary.py, the one place they are declared.
 *
 * A case: t_max must be finite and contact_max_step > 0 (rocking.sim.boundary
 * checks every field before a call); max_steps bounds the work of a run
 * (docs/simulation.md, rule 5); a non-finite right-hand side ends the run
 * with ROCKING_FAILED. */
#include "boundary.h"

/* Caller-owned buffers for a recorded history of at most `capacity` samples. */
typedef struct rocking_history {
    int64_t capacity;
    double *t;       /* [capacity] */
    double *y;       /* [capacity * model_ny()], one state after the other */
    int32_t *phase;  /* [capacity], enum rocking_phase */
    double *ag;      /* [capacity], ground acceleration at t */
    double *floor;   /* NULL, or [capacity * 4]: the slip u, its speed du, the floor's normal force N and
                        tangential force F on the block (a model with friction; else zeros) */
    int32_t *slide;  /* NULL, or [capacity]: the slip's sign sigma, 0 while the contact sticks */
    double *flight;  /* NULL, or [capacity * 3]: the reference corner's height v above the floor, its rate dv,
                        and 1.0 in flight, else 0.0 (a model with flight; else zeros) */
} rocking_history;

/* Sizes of the model the library was built with. */
int rocking_model_nq(void);
int rocking_model_ny(void);
int rocking_model_np(void);
int rocking_api_version(void);
/* The layout the library was compiled with, for the loader to compare with
 * its own: offsets of the fields of rocking_case (then of rocking_result) in
 * the order of ROCKING_CASE_FIELDS (ROCKING_RESULT_FIELDS) written to
 * `offsets`, followed by sizeof(rocking_case) (sizeof(rocking_result)). */
void rocking_layout(int64_t *case_offsets, int64_t *result_offsets);
/* The values of ROCKING_CONSTANTS, in its order. */
void rocking_constants(double *out);

/* What the caller controls besides the cases; the entry points accept NULL
 * for it, and NULL for either pointer:
 *
 *   stop          a flag the runs read once per accepted step (and between the
 *                 runs of a batch): set it to non-zero from another thread and
 *                 every run reading it ends at once with status ROCKING_STOPPED
 *                 (its other results are then meaningless). NULL: never stopped.
 *   velocity_law  model_nq() flags, 1 where the coordinate's impact law is
 *                 "velocity" (manifest.json, options.impact_laws), 0 where it is
 *                 "momentum" (entry 0, theta, is ignored); the model header does
 *                 not carry them. The rest snap of an impact keeps what the law
 *                 keeps (docs/simulation.md, rule 2). NULL: "momentum" everywhere.
 */
typedef struct rocking_control {
    const volatile int32_t *stop;
    const int32_t *velocity_law;
} rocking_control;

/* Simulate one run.
 *
 *   p        model parameters, model_np() values in manifest order
 *   c        settings
 *   out      the result
 *   history  NULL, or buffers for the history: samples at the multiples of
 *            c->record_dt strictly inside each phase segment (dense output)
 *            and the states at every segment start and end (uplift, impact
 *            before and after, breakpoints, rest, overturning, end), in time
 *            order, consecutive duplicates dropped.
 *   control  NULL, or the stop flag and the impact laws (rocking_control)
 *
 * Returns the number of history samples the run produced (0 without
 * history). Only the first history->capacity are written: when the return
 * value exceeds the capacity, call again with buffers that large (the run is
 * deterministic). Returns -1 if c->y0 / c->phase0 are inconsistent (out is then
 * left with status ROCKING_FAILED).
 */
int64_t rocking_simulate(const double *p, const rocking_case *c, rocking_result *out, rocking_history *history,
                         const rocking_control *control);

/* Simulate n runs of the same model without history: case i with the
 * parameters p + i * model_np() (row-major n x model_np()), result in out[i].
 * The runs go in lanes (lanes.h): case i gives rocking_simulate's statuses, events
 * and verdicts, its maxima to the last bits of sin and cos; with the lanes off
 * (ROCKING_LANES=0, rocking_simulate_batch_lanes) exactly what rocking_simulate
 * gives for it. An inconsistent
 * y0 / phase0 leaves its result with status ROCKING_FAILED. Once the stop
 * flag is set, the run in progress and every later one end with status
 * ROCKING_STOPPED. */
void rocking_simulate_batch(int64_t n, const double *p, const rocking_case *cases, rocking_result *out,
                            const rocking_control *control);

/* Ctrl-C while the caller's thread is in C. Python runs its SIGINT handler only
 * between bytecodes, so a call made from its main thread would finish first.
 * rocking_sigint_catch installs a handler that sets *stop (and notes the signal)
 * in place of the caller's, unless SIGINT is ignored; it returns 1 if it did.
 * rocking_sigint_release puts the caller's handler back and returns 1 if a
 * SIGINT came in between: the caller raises it again. One catch at a time per
 * library (Python's main thread); the only global state of the library. */
int rocking_sigint_catch(volatile int32_t *stop);
int rocking_sigint_release(void);

#ifdef __cplusplus
}
#endif

#endif
