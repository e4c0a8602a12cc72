/* The C simulation back end of rocking: the phase machine of docs/simulation.md
 * on a hand-written Dormand-Prince 5(4) integrator.
 *
 * sim.c knows no model: it is compiled together with one generated model and
 * uses only its generic names (MODEL_NQ, MODEL_NY, MODEL_NP, model_rocking_accel,
 * model_contact_accel, model_uplift, model_impact, model_energy,
 * model_uplift_energy, model_critical_angle). Build, e.g. for the model "omd":
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
 * Every entry point is a pure function of its arguments: no global state, no
 * allocation, safe to call from several threads at once.
 */
#ifndef ROCKING_SIM_H
#define ROCKING_SIM_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Bumped whenever a struct or a signature below changes. */
#define ROCKING_SIM_API_VERSION 2

/* Why a run ended: indices into rocking.problem.STATUS, plus a failure code. */
enum rocking_status {
    ROCKING_OVERTURNED = 0, /* |theta| reached pi/2 */
    ROCKING_REST = 1,       /* full contact after the pulse: energy above rest < energy_rest, or settled
                             * below the uplift energy (early_rest) */
    ROCKING_T_MAX = 2,      /* t_max reached */
    ROCKING_MAX_EVENTS = 3, /* uplifts + impacts reached max_events */
    ROCKING_FAILED = -1     /* the step size underflowed (non-finite right-hand side, ...) */
};

/* Phase codes of a recorded history (rocking.problem.CONTACT, PIVOT_A, PIVOT_A_PRIME). */
enum rocking_phase { ROCKING_CONTACT = 0, ROCKING_PIVOT_A = 1, ROCKING_PIVOT_A_PRIME = -1 };

/* One run's settings: the fields of rocking.problem.Problem except the model
 * and its parameters. t_max must be finite and contact_max_step > 0, or a run
 * may never end (rocking/c_backend.py checks both); a non-finite right-hand
 * side ends the run with ROCKING_FAILED. */
typedef struct rocking_case {
    double a_g;              /* pulse a_g sin(omega_g t + psi) on [0, t_p], 0 after [m/s^2] */
    double omega_g;          /* [rad/s] */
    double psi;              /* [rad] */
    double t_p;              /* end of the pulse, a breakpoint of the integration [s] */
    double t_max;            /* end of the run [s] */
    double rtol;             /* relative tolerance */
    const double *atol;      /* absolute tolerances, model_ny() values */
    double contact_max_step; /* largest step in full contact while t < t_p [s] */
    double dtheta_rest;      /* impact with outgoing |dtheta| below this: back to full contact */
    double energy_rest;      /* full contact after the pulse ends once E(y) - E(0) < this [J] */
    int64_t max_events;      /* the run ends when uplifts + impacts reach this */
    double record_dt;        /* history spacing [s] (<= 0: events only); unused without history */
    const double *y0;        /* initial state, model_ny() values; NULL: at rest (all zeros) */
    int32_t phase0;          /* initial phase: 0 (needs theta = dtheta = 0), +1 or -1 (s theta >= 0) */
    int32_t early_rest;      /* nonzero: full contact after the pulse below the uplift energy ends the run
                              * at the next extremum of q[1] (docs/simulation.md, rule 4) */
} rocking_case;

/* One run's answer: the scalar fields of rocking.problem.Response. 64 bytes,
 * no padding, so that an array of them maps onto a NumPy structured dtype. */
typedef struct rocking_result {
    int32_t status;     /* enum rocking_status */
    int32_t overturned; /* 0 or 1 */
    int64_t impacts;    /* impacts at theta = 0 */
    int64_t uplifts;    /* uplifts from full contact */
    double t_overturn;  /* NaN unless overturned */
    double t_critical;  /* first time |theta| passed the critical angle (NaN: never) */
    double theta_max;   /* largest |theta| */
    double x_max;       /* largest |q[1]| (0 for a one-coordinate model) */
    double t_end;       /* when the run ended */
} rocking_result;

/* Caller-owned buffers for a recorded history of at most `capacity` samples. */
typedef struct rocking_history {
    int64_t capacity;
    double *t;       /* [capacity] */
    double *y;       /* [capacity * model_ny()], one state after the other */
    int32_t *phase;  /* [capacity], enum rocking_phase */
    double *ag;      /* [capacity], ground acceleration at t */
} rocking_history;

/* Sizes of the model the library was built with, and of rocking_result. */
int rocking_model_nq(void);
int rocking_model_ny(void);
int rocking_model_np(void);
int rocking_result_size(void);
int rocking_api_version(void);
/* First step of a rocking phase after an impact, as a fraction of the
 * expected length of its half-cycle (the NumPy back end uses the same). */
double rocking_first_step_fraction(void);

/* Simulate one run.
 *
 *   p        model parameters, model_np() values in manifest order
 *   c        settings
 *   out      the result
 *   history  NULL, or buffers for the history: samples at the multiples of
 *            c->record_dt strictly inside each phase segment (dense output)
 *            and the states at every segment start and end (uplift, impact
 *            before and after, pulse end, rest, overturning, end), in time
 *            order, consecutive duplicates dropped.
 *
 * Returns the number of history samples the run produced (0 without
 * history). Only the first history->capacity are written: when the return
 * value exceeds the capacity, call again with buffers that large (the run is
 * deterministic). Returns -1 if c->y0 / c->phase0 are inconsistent (out is then
 * left with status ROCKING_FAILED).
 */
int64_t rocking_simulate(const double *p, const rocking_case *c, rocking_result *out, rocking_history *history);

/* Simulate n runs of the same model, each from rest, without history.
 *
 *   p                 n x model_np(), row-major
 *   a_g ... t_max     n values each
 *   atol              n x model_ny(), row-major
 *   contact_max_step, dtheta_rest, energy_rest   n values each
 *   rtol, max_events, early_rest   common to all runs
 *   out               n results
 *
 * Case i gives exactly what rocking_simulate gives for the same settings.
 */
void rocking_simulate_batch(int64_t n, const double *p, const double *a_g, const double *omega_g, const double *psi,
                            const double *t_p, const double *t_max, const double *atol,
                            const double *contact_max_step, const double *dtheta_rest, const double *energy_rest,
                            double rtol, int64_t max_events, int32_t early_rest, rocking_result *out);

#ifdef __cplusplus
}
#endif

#endif
