/* The phase machine of docs/simulation.md on a hand-written Dormand-Prince 5(4).
 *
 * Layout, bottom-up:
 *   1. the model as an ODE: right-hand side of one phase, ground acceleration;
 *   2. the integrator: DOPRI5 step with error control, initial step, dense output
 *      (knows nothing about events or phases);
 *   3. events: functions of (t, y), detection of a crossing over an accepted
 *      step, location on the dense output (knows nothing about what an event does);
 *   4. the phase machine: segments between events and breakpoints, and what
 *      happens at each event (uplift, impact, rest, overturning);
 *   5. the entry points of sim.h;
 *   6. Ctrl-C: a SIGINT handler that sets the stop flag of the call in progress.
 *
 * Only the generic names of the model header are used, so the same file serves
 * every generated model. No allocation, no global state but the SIGINT handler's
 * (section 6): the tables below are constants, everything else lives in the
 * caller's stack frame (the stop flag of rocking_control is the caller's).
 */
#if !defined(_WIN32) && !defined(_POSIX_C_SOURCE)
#define _POSIX_C_SOURCE 200809L /* sigaction under -std=c99 */
#endif
#include <float.h>
#include <math.h>
#include <signal.h>
#include <stddef.h>
#include <string.h>

#ifndef MODEL_NQ
#ifndef ROCKING_MODEL_HEADER
#error "compile with -DROCKING_MODEL_HEADER='\"<model>.h\"' (or -DROCKING_GENERIC_NAMES -include <model>.h)"
#endif
#ifndef ROCKING_GENERIC_NAMES
#define ROCKING_GENERIC_NAMES
#endif
#include ROCKING_MODEL_HEADER
#endif

#include "phases.h"
#include "sim.h"

#define NQ MODEL_NQ
#define NY MODEL_NY
/* The state a run carries: (q, dq), and on a model with friction the slip u = y[NY] and its speed
 * du = y[NY + 1] (docs/model.md section 15). A stuck phase integrates the first NY components alone, with
 * the operations of a model without friction; a sliding phase all NS. */
#ifdef MODEL_FRICTION
#define NS (NY + 2)
#else
#define NS NY
#endif
/* A model with flight functions (docs/model.md section 16) integrates in flight the rocking state and u, du
 * of the reference corner, then its height v = y[NY + 2] above the floor and its rate dv = y[NY + 3]: NF
 * components. NA: all that a state holds. */
#ifdef MODEL_FLIGHT
#ifndef MODEL_FRICTION
#error "a model with flight functions has those of friction too (derive/)"
#endif
#define NF (NY + 4)
#define NA NF
#else
#define NA NS
#endif

/* Inline a function into every caller, so that each copy knows its constant arguments (the number of
 * components a stepper integrates); and keep one out of line (the stepper, as one function for its stages). */
#if defined(__GNUC__) || defined(__clang__)
#define ALWAYS_INLINE inline __attribute__((always_inline))
#define NOINLINE __attribute__((noinline))
#else
#define ALWAYS_INLINE inline
#define NOINLINE
#endif

/* pi and pi/2: M_PI is not C99. */
#define PI 3.14159265358979323846
/* The model has flight functions: the lift-off event on every floor, and the flight phase (docs/model.md 16). */
#ifdef MODEL_FLIGHT
#define FLIGHT 1
#else
#define FLIGHT 0
#endif
#define HALF_PI 1.57079632679489661923

/* ------------------------------------------------------------------------ */
/* 1. The model as an ODE                                                    */
/* ------------------------------------------------------------------------ */

/* End-stop sides (the outputs of model_stop_gaps) that the events can follow. */
#define MAX_STOP_SIDES 4
#if MODEL_NSTOPS > MAX_STOP_SIDES
#error "the model has more end-stop sides than sim.c follows: raise MAX_STOP_SIDES"
#endif

/* The generated constants of a run (model_prepare) in the current regime of
 * the stops, one array per pivot. A gap event ends a segment (rule 6), so the
 * regime is constant within one: the right-hand side reads it from the
 * constants, with no condition on the state. */
#define NK (MODEL_NK > 0 ? MODEL_NK : 1)
typedef struct constants {
    double about[2][NK];         /* [0]: s = +1, [1]: s = -1 */
    int stop_on[MAX_STOP_SIDES]; /* the regime: each stop side's bumper acts */
    double memory[MAX_STOP_SIDES]; /* the regime's memory: a Hunt-Crossley side's v_in (0: none) */
    const double *p;             /* the model's parameters */
} constants;

#if MODEL_NREGIME > MODEL_NSTOPS
/* Per stop side, the least v_in of a Hunt-Crossley pad, 0 for a side without memory. */
static const double STOP_FLOORS[MODEL_NSTOPS] = MODEL_STOP_FLOORS;
#endif

/* The regime's inputs of model_prepare from k->stop_on and k->memory: the indicators
 * first, then the v_in of each side with memory (model.h). */
static void regime_inputs(const constants *k, double *on)
{
    int i, j = MODEL_NSTOPS;
    for (i = 0; i < MAX_STOP_SIDES; ++i)
        on[i] = k->stop_on[i] ? 1.0 : 0.0;
#if MODEL_NREGIME > MODEL_NSTOPS
    for (i = 0; i < MODEL_NSTOPS; ++i)
        if (STOP_FLOORS[i] > 0.0)
            on[j++] = k->memory[i];
#endif
    (void)j;
}

/* The constants of both pivots in the regime stop_on (MAX_STOP_SIDES flags) with the memory k->memory. */
static void constants_prepare(constants *k, const double *p, const int *stop_on)
{
    double on[2 * MAX_STOP_SIDES];
    memcpy(k->stop_on, stop_on, sizeof k->stop_on);
    regime_inputs(k, on);
    k->p = p;
    model_prepare(1.0, on, p, k->about[0]);
    model_prepare(-1.0, on, p, k->about[1]);
}

/* Regimes a run keeps the constants of: every combination of the stop sides' flags when the
 * regime is the flags alone; a Hunt-Crossley memory makes the regimes a continuum (none kept). */
#if MODEL_NSTOPS > 0 && MODEL_NREGIME == MODEL_NSTOPS
#define KEPT_REGIMES (1 << MODEL_NSTOPS)
#else
#define KEPT_REGIMES 0
#endif

/* The constants of the regimes a run has prepared: a mass that bounces on a pad switches between
 * the same two regimes at every contact, and preparing costs far more than a copy. */
typedef struct regime_store {
    int ready[KEPT_REGIMES > 0 ? KEPT_REGIMES : 1];
    double about[KEPT_REGIMES > 0 ? KEPT_REGIMES : 1][2][NK];
} regime_store;

#if KEPT_REGIMES > 0
/* The store's index of the regime stop_on. */
static int regime_key(const int *stop_on)
{
    int i, key = 0;
    for (i = 0; i < MODEL_NSTOPS; ++i)
        key |= (stop_on[i] != 0) << i;
    return key;
}
#endif

/* Keep k's constants for its regime (none kept where a pad's memory makes the regimes a continuum). */
static void regime_keep(regime_store *store, const constants *k)
{
#if KEPT_REGIMES > 0
    const int key = regime_key(k->stop_on);
    memcpy(store->about[key], k->about, sizeof k->about);
    store->ready[key] = 1;
#else
    (void)store, (void)k;
#endif
}

/* k in the regime stop_on: the kept constants of that regime, or prepared (and kept). */
static void constants_switch(constants *k, regime_store *store, const int *stop_on)
{
#if KEPT_REGIMES > 0
    const int key = regime_key(stop_on);
    if (store->ready[key]) {
        memcpy(k->stop_on, stop_on, sizeof k->stop_on);
        memcpy(k->about, store->about[key], sizeof k->about);
        return;
    }
#endif
    constants_prepare(k, k->p, stop_on);
    regime_keep(store, k);
}

/* The constants about the pivot s at the effective gravity g + agy: the vertical ground
 * acceleration enters the equations only with gravity (docs/model.md section 14), so the
 * model's functions read it from constants prepared with p's g moved by agy. */
static void constants_at_gravity(const constants *k, double s, double agy, double *cst)
{
    double on[2 * MAX_STOP_SIDES], p[MODEL_NP];
    memcpy(p, k->p, sizeof p);
    p[MODEL_P_GRAVITY] += agy;
    regime_inputs(k, on);
    model_prepare(s, on, p, cst);
}

/* The constants in the regime stop_on, prepared again only if it is a new one. */
static void constants_regime(constants *k, const int *stop_on)
{
    if (memcmp(k->stop_on, stop_on, sizeof k->stop_on) != 0)
        constants_prepare(k, k->p, stop_on);
}

/* Side i's pad starts pushing at y: a new contact if its penetration rises (its v_in recorded, at its
 * floor at least), else a released pad of the same contact pushes again (kept). With start set,
 * every side's v_in is that of a contact starting at y (the run's start). The constants are not
 * prepared again: the caller does. */
static void stop_memory_record(constants *k, const double *y, int i, int start)
{
#if MODEL_NREGIME > MODEL_NSTOPS
    double rates[MODEL_NSTOPS];
    int j;
    model_stop_approach_prepared(y, 0.0, k->about[0], rates);
    for (j = 0; j < MODEL_NSTOPS; ++j)
        if (STOP_FLOORS[j] > 0.0 && (start || (j == i && rates[j] >= 0.0)))
            k->memory[j] = fmax(rates[j], STOP_FLOORS[j]);
#else
    (void)k, (void)y, (void)i, (void)start;
#endif
}

/* Every side's v_in that of a contact starting at y (the run's start), the constants prepared
 * again for it in the regime clear; without a pad's memory nothing changes, nor is prepared. */
static void stop_memory_start(constants *k, const double *y, const int *clear)
{
#if MODEL_NREGIME > MODEL_NSTOPS
    stop_memory_record(k, y, -1, 1);
    constants_prepare(k, k->p, clear);
#else
    (void)k, (void)y, (void)clear;
#endif
}

#if MODEL_NSTOPS > 0
/* A jump of the velocities (an impact and its rest snap) from before to after with the mass in a
 * Hunt-Crossley pad: where its ddelta changed, the contact goes on at v_in = max(v_in, ddelta)
 * (rule 6); the constants are prepared again where a v_in grew. */
static void stop_memory_jump(constants *k, const double *before, const double *after)
{
#if MODEL_NREGIME > MODEL_NSTOPS
    double old[MODEL_NSTOPS], now[MODEL_NSTOPS], gaps[MODEL_NSTOPS];
    int j, grew = 0;
    model_stop_approach_prepared(before, 0.0, k->about[0], old);
    model_stop_approach_prepared(after, 0.0, k->about[0], now);
    model_stop_gaps_prepared(after, 0.0, k->about[0], gaps);
    for (j = 0; j < MODEL_NSTOPS; ++j)
        if (STOP_FLOORS[j] > 0.0 && gaps[j] > 0.0 && now[j] != old[j] && now[j] > k->memory[j]) {
            k->memory[j] = now[j];
            grew = 1;
        }
    if (grew)
        constants_prepare(k, k->p, k->stop_on);
#else
    (void)k, (void)before, (void)after;
#endif
}
#endif

/* The constants about the pivot s; full contact uses those of s = +1, as
 * the functions evaluated there do not depend on the pivot. */
static const double *about(const constants *k, double s)
{
    return k->about[s < 0.0];
}

/* f(t) of an analytic motion (docs/model.md section 12), the operations of
 * rocking/model/motion.py's SHAPES, so that both back ends see the same bits. */
static double pulse_shape(const rocking_case *c, double t)
{
    switch (c->motion) {
    case ROCKING_MOTION_SINE:
        return sin(c->omega_g * t + c->psi);
    case ROCKING_MOTION_COSINE:
        return cos(c->omega_g * t);
    case ROCKING_MOTION_RICKER: {
        const double u = 0.5 * c->omega_g * (t - c->t_c), u2 = u * u;
        return (1.0 - 2.0 * u2) * exp(-u2);
    }
    case ROCKING_MOTION_RICKER_ANTI: {
        const double u = c->omega_g * (t - c->t_c) / sqrt(6.0), u2 = u * u;
        return -(u * (3.0 - 2.0 * u2) * exp(-u2)) / ROCKING_RICKER_ANTI_PEAK;
    }
    case ROCKING_MOTION_MP: {
        const double phi = c->omega_g * (t - c->t_c), g = c->shape;
        return -0.5 * (sin(phi / g) / g * cos(phi + c->psi) + (1.0 + cos(phi / g)) * sin(phi + c->psi));
    }
    default:
        return 0.0; /* not reached: a sampled motion is interpolated */
    }
}

/* The sample interval [k dt, (k + 1) dt) holding t, k within [0, n - 2]:
 * floor(t / dt) corrected for the rounding of the ratio (motion.py's sample_piece). */
static double pulse_piece(const rocking_case *c, double t)
{
    const double dt = c->pulse_dt;
    double k = floor(t / dt);
    if ((k + 1.0) * dt <= t)
        k += 1.0;
    if (k * dt > t)
        k -= 1.0;
    return fmin(fmax(k, 0.0), (double)(c->n_samples - 2));
}

/* The linear interpolation of samples a at c's spacing on the piece k (motion.py's interpolate). */
static double interpolate(const rocking_case *c, const double *a, double k, double t)
{
    const int64_t i = (int64_t)k;
    return a[i] + (a[i + 1] - a[i]) * ((t - k * c->pulse_dt) / c->pulse_dt);
}

/* The vertical ground acceleration a_v f_v(t) inside [0, t_p] on the piece k of a sampled
 * motion (docs/model.md section 14): the horizontal shape psi_v / omega_g ahead, or the
 * vertical samples. */
static double vertical_in(const rocking_case *c, double k, double t)
{
    if (c->motion == ROCKING_MOTION_SAMPLED)
        return c->a_v * interpolate(c, c->v_samples, k, t);
    return c->a_v * pulse_shape(c, t + c->psi_v / c->omega_g);
}

/* a_g f(t) on [0, t_p], a sampled motion on the piece holding t (the history,
 * the start of a contact phase). */
static double pulse_at(const rocking_case *c, double t)
{
    if (!(t >= 0.0 && t <= c->t_p))
        return 0.0;
    if (c->motion == ROCKING_MOTION_SAMPLED)
        return c->a_g * interpolate(c, c->samples, pulse_piece(c, t), t);
    return c->a_g * pulse_shape(c, t);
}

/* The vertical ground acceleration at t (0 outside [0, t_p] or without one). */
static double vertical_at(const rocking_case *c, double t)
{
    if (c->a_v == 0.0 || !(t >= 0.0 && t <= c->t_p))
        return 0.0;
    return vertical_in(c, c->motion == ROCKING_MOTION_SAMPLED ? pulse_piece(c, t) : 0.0, t);
}

/* One phase's right-hand side: y' = (dq, accelerations of the phase). */
typedef struct ode {
    const constants *k; /* of the model's parameters */
    int phase;       /* 0: full contact; +1 / -1: rocking about A / A' */
    int sigma;       /* 0: the contact sticks; +1 / -1: it slides, du of that sign */
    int flying;      /* the block flies, its reference corner s = phase (docs/model.md section 16) */
    int ny;          /* the components integrated: NY stuck, NS sliding, NF flying */
    double mu_slip;  /* mu_k sigma: the friction force on the block is -mu_slip N */
    double on[2 * MAX_STOP_SIDES]; /* the regime's inputs of the friction functions (regime_inputs) */
    const double *cst; /* the constants of the phase: about(k, phase), those of s = +1 in full contact */
    int pulse_on;    /* the segment lies in [0, t_p] */
    int vertical;    /* pulse_on and the motion has a vertical component */
    int rhs;         /* ode_rhs_kind of the above, set with them */
    const rocking_case *c; /* the ground motion */
    double piece;    /* a sampled motion: the sample interval of the current step */
    /* The last a_g f(t) of an analytic motion and its t: a step's last two stages
     * and its events all read it at the step's end. */
    double memo_t, memo_ag;
    struct lane *lane; /* the lane of a batch in lanes running this run (lanes.c), or NULL */
} ode;

/* Ground acceleration inside a segment. A segment never straddles t_p, so it
 * sees either the motion or 0 for all its stages (even one an ulp past t_p),
 * and a step of a sampled motion never straddles a sample time, so its stages
 * see one linear piece: one smooth function per step, no kink inside. */
static double ode_ag(ode *o, double t)
{
    if (t == o->memo_t) /* set below alone, and cleared where a segment starts */
        return o->memo_ag;
    if (!o->pulse_on)
        return 0.0;
    if (o->c->motion == ROCKING_MOTION_SAMPLED)
        return o->c->a_g * interpolate(o->c, o->c->samples, o->piece, t);
    o->memo_t = t;
    /* The one-sine, the common pulse, without pulse_shape's call and switch (the same operations). */
    if (o->c->motion == ROCKING_MOTION_SINE)
        o->memo_ag = o->c->a_g * sin(o->c->omega_g * t + o->c->psi);
    else
        o->memo_ag = o->c->a_g * pulse_shape(o->c, t);
    return o->memo_ag;
}

/* The constants about s at t: the phase's, or with a vertical component those at the
 * effective gravity g + agy(t), written into at_gravity. */
static const double *gravity_constants(const ode *o, double s, double t, double *at_gravity)
{
    if (!o->vertical)
        return about(o->k, s);
    constants_at_gravity(o->k, s, vertical_in(o->c, o->piece, t), at_gravity);
    return at_gravity;
}

/* The right-hand side without a vertical component: inline in every stage (the call around it
 * was 4 % of a run's instructions on the bench map; ode_ag inline too was more, not less).
 * pulse_on and contact are o->pulse_on and o->phase == 0, constants of each inlined copy. */
static inline void ode_rhs_level(ode *o, double t, const double *y, double *dy, int pulse_on, int contact)
{
    const double ag = pulse_on ? ode_ag(o, t) : 0.0;
    /* In full contact contact_accel returns ddtheta = 0 and dtheta is 0, so
     * theta and dtheta stay exactly 0 while the whole state is integrated (the
     * error norm then runs over the same components in every phase). */
    if (contact)
        model_contact_accel_prepared(y, ag, o->cst, dy + NQ);
    else
        model_rocking_accel_prepared(y, ag, o->cst, dy + NQ);
    memcpy(dy, y + NQ, NQ * sizeof *dy);
}

/* The right-hand side with a vertical component: the constants at the effective gravity of t.
 * Out of line, so that the stages of the level case keep their right-hand side inline. */
static void ode_rhs_vertical(ode *o, double t, const double *y, double *dy)
{
    const double ag = ode_ag(o, t);
    double at_gravity[NK];
    const double *cst = gravity_constants(o, o->phase < 0 ? -1.0 : 1.0, t, at_gravity);
    if (o->phase == 0)
        model_contact_accel_prepared(y, ag, cst, dy + NQ);
    else
        model_rocking_accel_prepared(y, ag, cst, dy + NQ);
    memcpy(dy, y + NQ, NQ * sizeof *dy);
}

#ifdef MODEL_FRICTION
/* The regime's inputs of the friction functions: NULL without stops (they read none). */
static const double *friction_on(const ode *o)
{
    return MODEL_NSTOPS > 0 ? o->on : NULL;
}

/* The vertical ground acceleration of the segment at t (0 without one). */
static double ode_agy(const ode *o, double t)
{
    return o->vertical ? vertical_in(o->c, o->piece, t) : 0.0;
}

/* The accelerations of a sliding phase, then ddu and the floor's normal force N, into out[NQ + 2]. */
static void slide_accel(ode *o, double t, const double *y, double *out)
{
    const double ag = ode_ag(o, t), agy = ode_agy(o, t);
    if (o->phase == 0)
        model_contact_slide_accel(1.0, y, ag, agy, o->k->p, friction_on(o), o->mu_slip, out);
    else
        model_slide_accel((double)o->phase, y, ag, agy, o->k->p, friction_on(o), o->mu_slip, out);
}

/* The right-hand side of a sliding phase: y' = (dq, ddq, du, ddu), NS components. */
static void ode_rhs_slide(ode *o, double t, const double *y, double *dy)
{
    double out[NQ + 2];
    slide_accel(o, t, y, out);
    memcpy(dy, y + NQ, NQ * sizeof *dy);
    memcpy(dy + NQ, out, NQ * sizeof *dy);
    dy[NY] = y[NY + 1];
    dy[NY + 1] = out[NQ];
}
#endif

#ifdef MODEL_FLIGHT
/* The right-hand side in flight: y' = (dq, ddq, du, ddu, dv, ddv), NF components, ddu and ddv those of the
 * reference corner s = o->phase relative to the ground (generated flight_accel). */
static void ode_rhs_flight(ode *o, double t, const double *y, double *dy)
{
    double out[NQ + 2];
    model_flight_accel((double)o->phase, y, ode_ag(o, t), ode_agy(o, t), o->k->p, friction_on(o), out);
    memcpy(dy, y + NQ, NQ * sizeof *dy);
    memcpy(dy + NQ, out, NQ * sizeof *dy);
    dy[NY] = y[NY + 1];
    dy[NY + 1] = out[NQ];
    dy[NY + 2] = y[NY + 3];
    dy[NY + 3] = out[NQ + 1];
}
#endif

/* y' = (dq, accelerations of the phase) at (t, y), outside the stages of a step. */
static inline void ode_rhs(ode *o, double t, const double *y, double *dy)
{
#ifdef MODEL_FLIGHT
    if (o->flying)
        ode_rhs_flight(o, t, y, dy);
    else
#endif
#ifdef MODEL_FRICTION
    if (o->sigma != 0)
        ode_rhs_slide(o, t, y, dy);
    else
#endif
    if (o->vertical)
        ode_rhs_vertical(o, t, y, dy);
    else
        ode_rhs_level(o, t, y, dy, o->pulse_on, o->phase == 0);
}

/* ------------------------------------------------------------------------ */
/* 2. Dormand-Prince 5(4) with its continuous extension                      */
/* ------------------------------------------------------------------------ */

enum { STAGES = 7 };

/* Butcher tableau. Row 7 is the 5th-order solution itself (FSAL: its stage is
 * f at the new point, the first stage of the next step). */
static const double RK_C[STAGES] = {0.0, 1.0 / 5, 3.0 / 10, 4.0 / 5, 8.0 / 9, 1.0, 1.0};
static const double RK_A[STAGES][STAGES - 1] = {
    {0.0, 0.0, 0.0, 0.0, 0.0, 0.0},
    {1.0 / 5, 0.0, 0.0, 0.0, 0.0, 0.0},
    {3.0 / 40, 9.0 / 40, 0.0, 0.0, 0.0, 0.0},
    {44.0 / 45, -56.0 / 15, 32.0 / 9, 0.0, 0.0, 0.0},
    {19372.0 / 6561, -25360.0 / 2187, 64448.0 / 6561, -212.0 / 729, 0.0, 0.0},
    {9017.0 / 3168, -355.0 / 33, 46732.0 / 5247, 49.0 / 176, -5103.0 / 18656, 0.0},
    {35.0 / 384, 0.0, 500.0 / 1113, 125.0 / 192, -2187.0 / 6784, 11.0 / 84},
};
/* Difference of the 5th- and the embedded 4th-order weights: the local error estimate. */
static const double RK_E[STAGES] = {71.0 / 57600,      0.0,         -71.0 / 16695, 71.0 / 1920,
                                    -17253.0 / 339200, 22.0 / 525, -1.0 / 40};
/* Continuous extension of Hairer's DOPRI5 (4th order, exact at both ends of the step). */
static const double RK_D[STAGES] = {-12715105075.0 / 11282082432.0,  0.0,
                                    87487479700.0 / 32700410799.0,   -10690763975.0 / 1880347072.0,
                                    701980252875.0 / 199316789632.0, -1453857185.0 / 822651844.0,
                                    69997945.0 / 29380423.0};

/* Step-size control of docs/simulation.md (as SciPy's RK45). The exponent is
 * 1/(q+1) with q = 4, the order of the embedded error estimate. */
#define SAFETY 0.9
#define MIN_FACTOR 0.2
#define MAX_FACTOR 10.0
#define ERROR_EXPONENT (-1.0 / 5.0)
/* Shortcuts that skip work without changing any result: a test builds the
 * library with -DROCKING_NO_SHORTCUTS too and compares the two bit for bit. */
#ifdef ROCKING_NO_SHORTCUTS
#define SHORTCUTS 0
#else
#define SHORTCUTS 1
#endif
/* SAFETY err^ERROR_EXPONENT >= MAX_FACTOR for err <= (SAFETY / MAX_FACTOR)^5 =
 * 5.9049e-6; a little below it, so that rounding cannot matter. */
#define SATURATED 5.9e-6

typedef struct tolerance {
    double rtol;
    const double *atol; /* NS values */
} tolerance;

/* The integrator's state. It integrates the first n components (NY or NS); y and y_old hold all NS, the
 * others constant (a stuck contact's u and du = 0), so that the whole state reads from it. */
typedef struct dopri {
    int n;
    double t, y[NA], f[NA]; /* current point; f = rhs(t, y) */
    double t_old, h;        /* the last accepted step: [t_old, t], h = t - t_old */
    double y_old[NA];
    double k[STAGES][NA];   /* its stages: k[0] = f(t_old), k[6] = f(t) */
    double dense[5][NA];    /* its continuous extension, once dense_ready */
    int dense_ready;
    double h_next; /* proposed size of the next step */
    int64_t evaluations; /* of the right-hand side, over the whole run (rule 5) */
} dopri;

static double max2(double a, double b)
{
    return a > b ? a : b;
}

static double min2(double a, double b)
{
    return a < b ? a : b;
}

/* Smallest step SciPy allows at t: 10 ulps, so that t + h != t. */
static double min_step_at(double t)
{
    return 10.0 * (nextafter(t, INFINITY) - t);
}

/* h < min_step_at(t), without nextafter in the common case: an ulp of t is
 * at most eps |t|. */
static int below_min_step(double h, double t)
{
    return h <= 16.0 * DBL_EPSILON * fabs(t) && h < min_step_at(t);
}

/* RMS norm of v / scale over n components (Hairer's norm). */
static inline double rms_ratio(const double *v, const double *scale, int n)
{
    double sum = 0.0;
    int i;
    for (i = 0; i < n; ++i) {
        const double r = v[i] / scale[i];
        sum += r * r;
    }
    return sqrt(sum / n);
}

/* Hairer's initial step heuristic (SciPy's select_initial_step) over the first n components (a constant of
 * each copy): a step whose explicit Euler error estimate would be about 1 % of the tolerance. */
static ALWAYS_INLINE double initial_step_of(ode *o, const tolerance *tol, double t0, const double *y0,
                                            const double *f0, double span, int n)
{
    double scale[NA], y1[NA], f1[NA], df[NA];
    double d0, d1, d2, h0, h1;
    int i;
    if (span <= 0.0)
        return 0.0;
    for (i = 0; i < n; ++i)
        scale[i] = tol->atol[i] + tol->rtol * fabs(y0[i]);
    d0 = rms_ratio(y0, scale, n);
    d1 = rms_ratio(f0, scale, n);
    h0 = (d0 < 1e-5 || d1 < 1e-5) ? 1e-6 : 0.01 * d0 / d1;
    h0 = fmin(h0, span);
    for (i = n; i < NA; ++i) /* the components not integrated, constant */
        y1[i] = y0[i];
    for (i = 0; i < n; ++i)
        y1[i] = y0[i] + h0 * f0[i];
    ode_rhs(o, t0 + h0, y1, f1);
    for (i = 0; i < n; ++i)
        df[i] = f1[i] - f0[i];
    d2 = rms_ratio(df, scale, n) / h0;
    if (d1 <= 1e-15 && d2 <= 1e-15)
        h1 = fmax(1e-6, h0 * 1e-3);
    else
        h1 = pow(0.01 / fmax(d1, d2), 1.0 / 5.0);
    return fmin(fmin(100.0 * h0, h1), span);
}

/* initial_step_of the components the segment integrates. */
static double initial_step(ode *o, const tolerance *tol, double t0, const double *y0, const double *f0, double span)
{
#ifdef MODEL_FLIGHT
    if (o->ny == NF)
        return initial_step_of(o, tol, t0, y0, f0, span, NF);
#endif
#ifdef MODEL_FRICTION
    if (o->ny == NS)
        return initial_step_of(o, tol, t0, y0, f0, span, NS);
#endif
    return initial_step_of(o, tol, t0, y0, f0, span, NY);
}

/* Start integrating at (t, y): f and the first step size, h_first if > 0,
 * else by Hairer's heuristic. */
static void dopri_start(dopri *d, ode *o, const tolerance *tol, double t, const double *y, double t_bound,
                        double h_first)
{
    d->n = o->ny;
    d->t = t;
    memcpy(d->y, y, sizeof d->y);
    memcpy(d->y_old, y, sizeof d->y_old); /* its components not integrated stay */
    ode_rhs(o, t, y, d->f);
    /* initial_step evaluates the right-hand side once, unless the span is empty. */
    d->evaluations += (h_first > 0.0 || !(t_bound - t > 0.0)) ? 1 : 2;
    d->h_next = h_first > 0.0 ? min2(h_first, t_bound - t) : initial_step(o, tol, t, d->y, d->f, t_bound - t);
    d->t_old = t;
    d->h = 0.0;
    d->dense_ready = 0;
}

/* acc = sum_j w[j] k[j] over the first n stages, summed in stage order from
 * the first product (a sum from 0.0 differs only in a zero's sign, and cost
 * one addition per component and stage). Every call has a constant n and w (a row of a table): unrolled over
 * the stages, each inlined call keeps the components in vector registers and
 * loads each weight once (with the stages inside the components' loop, gcc
 * loaded them again for every pair of components). */
static inline void combine_stages(const double (*k)[NA], const double *w, int n, double *acc, int ny)
{
    int i, j;
    for (i = 0; i < ny; ++i)
        acc[i] = w[0] * k[0][i];
#pragma GCC unroll 8
    for (j = 1; j < n; ++j)
        for (i = 0; i < ny; ++i)
            acc[i] += w[j] * k[j][i];
}

/* The right-hand sides of a segment, one set of stages each (dopri_stages): whether the contact slides,
 * whether the ground moves vertically, else whether the pulse acts and whether in full contact. */
enum { ODE_VERTICAL, ODE_PULSE_CONTACT, ODE_PULSE_ROCKING, ODE_FREE_CONTACT, ODE_FREE_ROCKING, ODE_SLIDE, ODE_FLIGHT };

/* The right-hand side of the ode o's segment (enum above). */
static int ode_rhs_kind(const ode *o)
{
    if (o->flying)
        return ODE_FLIGHT;
    if (o->sigma != 0)
        return ODE_SLIDE;
    if (o->vertical)
        return ODE_VERTICAL;
    if (o->pulse_on)
        return o->phase == 0 ? ODE_PULSE_CONTACT : ODE_PULSE_ROCKING;
    return o->phase == 0 ? ODE_FREE_CONTACT : ODE_FREE_ROCKING;
}

/* Stage s (1..6) of a step of size h: its point into y, f there into d->k[s]. rhs (ode_rhs_kind) is
 * a constant of each inlined copy: the stages of a step test the segment's kind once. */
static ALWAYS_INLINE void dopri_stage(dopri *d, ode *o, int s, double h, double t_new, double *y, int rhs)
{
    double acc[NA];
    const double t = RK_C[s] == 1.0 ? t_new : d->t + RK_C[s] * h; /* the last stages sit at t_new, maybe a breakpoint */
    const int ny = rhs == ODE_FLIGHT ? NA : rhs == ODE_SLIDE ? NS : NY;
    int i;
    combine_stages((const double(*)[NA])d->k, RK_A[s], s, acc, ny);
    for (i = 0; i < ny; ++i)
        y[i] = d->y[i] + h * acc[i];
#ifdef MODEL_FLIGHT
    if (rhs == ODE_FLIGHT)
        ode_rhs_flight(o, t, y, d->k[s]);
    else
#endif
#ifdef MODEL_FRICTION
    if (rhs == ODE_SLIDE)
        ode_rhs_slide(o, t, y, d->k[s]);
    else
#endif
    if (rhs == ODE_VERTICAL)
        ode_rhs_vertical(o, t, y, d->k[s]);
    else
        ode_rhs_level(o, t, y, d->k[s], rhs == ODE_PULSE_CONTACT || rhs == ODE_PULSE_ROCKING,
                      rhs == ODE_PULSE_CONTACT || rhs == ODE_FREE_CONTACT);
}

/* The stages of a step of size h from d->t, into d->k; the new state into y_new.
 * Written out stage by stage (the coefficients stay in the tableau): each
 * combination then has a constant length the compiler can specialise. */
static ALWAYS_INLINE void dopri_stages_of(dopri *d, ode *o, double h, double t_new, double *y_new, int rhs)
{
    memcpy(d->k[0], d->f, (rhs == ODE_FLIGHT ? NA : rhs == ODE_SLIDE ? NS : NY) * sizeof *d->f);
    dopri_stage(d, o, 1, h, t_new, y_new, rhs);
    dopri_stage(d, o, 2, h, t_new, y_new, rhs);
    dopri_stage(d, o, 3, h, t_new, y_new, rhs);
    dopri_stage(d, o, 4, h, t_new, y_new, rhs);
    dopri_stage(d, o, 5, h, t_new, y_new, rhs);
    dopri_stage(d, o, 6, h, t_new, y_new, rhs);
    /* The last stage was evaluated at the 5th-order solution: y_new holds it. */
}

static ALWAYS_INLINE void dopri_stages(dopri *d, ode *o, double h, double t_new, double *y_new)
{
    switch (o->rhs) {
    case ODE_VERTICAL:
        dopri_stages_of(d, o, h, t_new, y_new, ODE_VERTICAL);
        break;
    case ODE_PULSE_CONTACT:
        dopri_stages_of(d, o, h, t_new, y_new, ODE_PULSE_CONTACT);
        break;
    case ODE_PULSE_ROCKING:
        dopri_stages_of(d, o, h, t_new, y_new, ODE_PULSE_ROCKING);
        break;
    case ODE_FREE_CONTACT:
        dopri_stages_of(d, o, h, t_new, y_new, ODE_FREE_CONTACT);
        break;
    default:
        dopri_stages_of(d, o, h, t_new, y_new, ODE_FREE_ROCKING);
        break;
    }
}

static inline double dopri_error(const dopri *d, const tolerance *tol, double h, const double *y_new, int ny)
{
    double err[NA], scale[NA];
    int i;
    combine_stages((const double(*)[NA])d->k, RK_E, STAGES, err, ny);
    for (i = 0; i < ny; ++i) {
        const double a = fabs(d->y[i]), b = fabs(y_new[i]);
        err[i] *= h;
        scale[i] = tol->atol[i] + tol->rtol * (a > b ? a : b);
    }
    return rms_ratio(err, scale, ny);
}

/* The stages and error of a step of a run in a lane, and that error's power (lanes.c). */
struct lane;
static double lanes_stages(dopri *d, ode *o, const tolerance *tol, double h, double t_new, double *y_new);
static double lanes_error_power(const struct lane *l, double err);

/* How a copy of dopri_step_of steps (a constant of each copy): libm's pow alone (a run outside the lanes: the
 * scalar path keeps its own code), a run in a lane (the stages over vectors, lanes.c), or either, read from the
 * run (the slip's and the flight's steppers). */
enum { STEP_SCALAR, STEP_LANE, STEP_EITHER };

/* err^ERROR_EXPONENT for the step-size control: libm's, or the lanes' for a run in a lane (how: dopri_step_of's). */
static inline double error_power(const ode *o, double err, int how)
{
    if (how == STEP_SCALAR)
        return pow(err, ERROR_EXPONENT);
    return how == STEP_LANE || o->lane != NULL ? lanes_error_power(o->lane, err) : pow(err, ERROR_EXPONENT);
}

/* One accepted step of the first ny components (a constant of each copy) towards t_bound, at most
 * max_step long. Returns 0, or -1 when the error cannot be controlled above the smallest step. */
static ALWAYS_INLINE int dopri_step_of(dopri *d, ode *o, const tolerance *tol, double t_bound, double max_step,
                                       int ny, int how)
{
    double y_new[NA];
    double h = min2(d->h_next, max_step);
    int rejected = 0;
    if (!(h > 0.0) || below_min_step(h, d->t)) /* NaN included */
        h = min_step_at(d->t);
    for (;;) {
        double t_new = d->t + h, err;
        if (t_new > t_bound)
            t_new = t_bound;
        h = t_new - d->t; /* the step actually taken, so that t_old + h == t exactly */
        if (how == STEP_LANE) {
            err = lanes_stages(d, o, tol, h, t_new, y_new);
        } else {
#ifdef MODEL_FLIGHT
            if (ny == NF)
                dopri_stages_of(d, o, h, t_new, y_new, ODE_FLIGHT);
            else
#endif
#ifdef MODEL_FRICTION
            if (ny == NS)
                dopri_stages_of(d, o, h, t_new, y_new, ODE_SLIDE);
            else
#endif
                dopri_stages(d, o, h, t_new, y_new);
            err = dopri_error(d, tol, h, y_new, ny);
        }
        d->evaluations += STAGES - 1;
        if (err < 1.0) {
            /* Below SATURATED the factor is MAX_FACTOR anyway: no pow (small rocking is nearly exact). */
            double factor =
                SHORTCUTS && err < SATURATED ? MAX_FACTOR : min2(MAX_FACTOR, SAFETY * error_power(o, err, how));
            if (rejected) /* no growth right after a rejection */
                factor = min2(1.0, factor);
            d->t_old = d->t;
            d->h = h;
            memcpy(d->y_old, d->y, ny * sizeof *d->y);
            d->t = t_new;
            memcpy(d->y, y_new, ny * sizeof *y_new);
            memcpy(d->f, d->k[STAGES - 1], ny * sizeof *d->f);
            d->dense_ready = 0;
            d->h_next = h * factor;
            return 0;
        }
        /* fmax ignores a NaN error: a non-finite state shrinks the step until it fails. */
        h *= fmax(MIN_FACTOR, SAFETY * error_power(o, err, how));
        rejected = 1;
        if (!(h > 0.0) || below_min_step(h, d->t))
            return -1;
    }
}

/* One accepted step (dopri_step_of) of a stuck contact's NY components. Its own function: with the sliding
 * copy in the same one, gcc compiled this one to 20 % more instructions on the bench map. */
static NOINLINE int dopri_step_stuck(dopri *d, ode *o, const tolerance *tol, double t_bound, double max_step)
{
    return dopri_step_of(d, o, tol, t_bound, max_step, NY, STEP_SCALAR);
}

/* dopri_step_stuck of a run in a lane: its stages over vectors (lanes.c). */
static NOINLINE int dopri_step_lane(dopri *d, ode *o, const tolerance *tol, double t_bound, double max_step)
{
    return dopri_step_of(d, o, tol, t_bound, max_step, NY, STEP_LANE);
}

#ifdef MODEL_FRICTION
/* One accepted step (dopri_step_of) of a sliding contact's NS components. */
static NOINLINE int dopri_step_slide(dopri *d, ode *o, const tolerance *tol, double t_bound, double max_step)
{
    return dopri_step_of(d, o, tol, t_bound, max_step, NS, STEP_EITHER);
}
#endif

#ifdef MODEL_FLIGHT
/* One accepted step (dopri_step_of) of a flying block's NF components. */
static NOINLINE int dopri_step_flight(dopri *d, ode *o, const tolerance *tol, double t_bound, double max_step)
{
    return dopri_step_of(d, o, tol, t_bound, max_step, NF, STEP_EITHER);
}
#endif

/* A stepper: dopri_step_stuck or dopri_step_slide, chosen once per segment (dopri_stepper). */
typedef int (*dopri_step_fn)(dopri *d, ode *o, const tolerance *tol, double t_bound, double max_step);

/* The stepper of the components d integrates, for the run o (in a lane or not). */
static dopri_step_fn dopri_stepper(const dopri *d, const ode *o)
{
#ifdef MODEL_FLIGHT
    if (d->n == NF)
        return dopri_step_flight;
#endif
#ifdef MODEL_FRICTION
    if (d->n == NS)
        return dopri_step_slide;
#else
    (void)d;
#endif
    return o->lane != NULL ? dopri_step_lane : dopri_step_stuck;
}

/* Take back the last accepted step and propose h_next instead. */
static void dopri_undo(dopri *d, double h_next)
{
    d->t = d->t_old;
    memcpy(d->y, d->y_old, sizeof d->y);
    memcpy(d->f, d->k[0], sizeof d->f);
    d->h = 0.0;
    d->dense_ready = 0;
    d->h_next = h_next;
}

/* Coefficients of the continuous extension of the first ny components (dopri_prepare_dense). */
static ALWAYS_INLINE void dopri_prepare_dense_of(dopri *d, int ny)
{
    double sum[NA];
    int i;
    combine_stages((const double(*)[NA])d->k, RK_D, STAGES, sum, ny);
    for (i = 0; i < ny; ++i) {
        const double dy = d->y[i] - d->y_old[i];
        const double bspl = d->h * d->k[0][i] - dy;
        d->dense[0][i] = d->y_old[i];
        d->dense[1][i] = dy;
        d->dense[2][i] = bspl;
        d->dense[3][i] = dy - d->h * d->k[STAGES - 1][i] - bspl;
        d->dense[4][i] = d->h * sum[i];
    }
}

/* Coefficients of the continuous extension, computed only for the steps that
 * need it (an event to locate, a sample to record). */
static void dopri_prepare_dense(dopri *d)
{
    if (d->dense_ready)
        return;
#ifdef MODEL_FLIGHT
    if (d->n == NF)
        dopri_prepare_dense_of(d, NF);
    else
#endif
#ifdef MODEL_FRICTION
    if (d->n == NS)
        dopri_prepare_dense_of(d, NS);
    else
#endif
        dopri_prepare_dense_of(d, NY);
    d->dense_ready = 1;
}

/* The coefficients of component i of the continuous extension, the operations of
 * dopri_prepare_dense for that component alone: the bound of a peak (peak_below_max) mostly
 * finds the step needs no location, and then no other component. */
static void dense_component(const dopri *d, int i, double *c)
{
    double sum = RK_D[0] * d->k[0][i];
    int j;
    for (j = 1; j < STAGES; ++j)
        sum += RK_D[j] * d->k[j][i];
    c[0] = d->y_old[i];
    c[1] = d->y[i] - d->y_old[i];
    c[2] = d->h * d->k[0][i] - c[1];
    c[3] = c[1] - d->h * d->k[STAGES - 1][i] - c[2];
    c[4] = d->h * sum;
}

/* Component i of the prepared dense output at th = (t - t_old) / h, th1 = 1 - th. */
static inline double dense_at(const dopri *d, double th, double th1, int i)
{
    return d->dense[0][i] +
           th * (d->dense[1][i] + th1 * (d->dense[2][i] + th * (d->dense[3][i] + th1 * d->dense[4][i])));
}

/* Component i of the dense output at t in [t_old, t]. */
static double dopri_dense1(dopri *d, double t, int i)
{
    double th;
    if (t == d->t)
        return d->y[i];
    dopri_prepare_dense(d);
    th = (t - d->t_old) / d->h;
    return dense_at(d, th, 1.0 - th, i);
}

/* An upper bound of |component i| of the dense output over the whole last
 * step, term by term: with u in [0, 1], u <= 1, u (1 - u) <= 1/4,
 * u^2 (1 - u) <= 4/27 and u^2 (1 - u)^2 <= 1/16; widened by 16 eps for the
 * rounding of any evaluation inside. */
static double dopri_dense_bound(const dopri *d, int i)
{
    double c[5], b;
    int j;
    if (d->dense_ready) {
        for (j = 0; j < 5; ++j)
            c[j] = d->dense[j][i];
    } else {
        dense_component(d, i, c);
    }
    b = fabs(c[0]) + fabs(c[1]) + 0.25 * fabs(c[2]) + (4.0 / 27.0) * fabs(c[3]) + 0.0625 * fabs(c[4]);
    return b * (1.0 + 16.0 * DBL_EPSILON);
}

/* The first ny components of the dense output at th (dopri_dense). */
static ALWAYS_INLINE void dopri_dense_of(const dopri *d, double th, double *y, int ny)
{
    int i;
    for (i = 0; i < ny; ++i)
        y[i] = dense_at(d, th, 1.0 - th, i);
}

/* The state on the dense output: dopri_dense1 of every integrated component, its set-up once; the others,
 * constant over the step, are left in y as they are (the whole state at the step's end). */
static void dopri_dense(dopri *d, double t, double *y)
{
    double th;
    if (t == d->t) {
        memcpy(y, d->y, sizeof d->y);
        return;
    }
    dopri_prepare_dense(d);
    th = (t - d->t_old) / d->h;
#ifdef MODEL_FLIGHT
    if (d->n == NF)
        dopri_dense_of(d, th, y, NF);
    else
#endif
#ifdef MODEL_FRICTION
    if (d->n == NS)
        dopri_dense_of(d, th, y, NS);
    else
#endif
        dopri_dense_of(d, th, y, NY);
}

/* ------------------------------------------------------------------------ */
/* 3. Events                                                                 */
/* ------------------------------------------------------------------------ */

enum event_kind {
    EV_UPLIFT_A,       /* contact: u_{+1} turns positive */
    EV_UPLIFT_A_PRIME, /* contact: u_{-1} turns positive */
    EV_REST,           /* contact after the pulse: E(y) - E(0) falls below energy_rest */
    EV_SAFE,           /* contact after the pulse: E(y) - E(0) falls below the uplift energy */
    EV_IMPACT,         /* rocking: s theta falls from > 0 to 0 */
    EV_OVERTURN,       /* rocking: s theta reaches pi/2 */
    EV_CRITICAL,       /* rocking: s theta - s theta_cr_s(y) turns positive (reported) */
    EV_THETA_PEAK,     /* rocking: dtheta changes sign (theta_max) */
    EV_X_PEAK,         /* any phase, with a damper: dq[1] changes sign (x_max) */
    EV_SETTLED,        /* contact once safe: dq[1] changes sign, the last extremum (ends the run) */
    EV_SLIP,           /* stuck, finite mu_s: mu_s N - |F| falls from > 0 to 0 */
    EV_STOP,           /* sliding: sigma du falls from > 0 to 0 */
    EV_LIFT_OFF,       /* finite mu_s: the floor's normal force N falls from > 0 to 0 */
    EV_SLIDE_UPLIFT_A, /* contact, sliding: u_{+1} with the friction force turns positive */
    EV_SLIDE_UPLIFT_A_PRIME, /* contact, sliding: u_{-1} with the friction force turns positive */
    EV_LANDING_S,      /* flight: the reference corner's height v falls from > 0 to 0 */
    EV_LANDING_O,      /* flight: the other corner's height falls from > 0 to 0 */
    EV_FLIGHT_OVERTURN, /* flight: |theta| reaches pi/2 */
    EV_JUMP_S,         /* flight: dv falls from > 0 to 0, a peak of v (jump_max) */
    EV_JUMP_O,         /* flight: the other corner's rate falls from > 0 to 0, a peak of its height (jump_max) */
    EV_GAP_CLOSE,      /* any phase: the contact of a stop side that does not push turns positive (one kind per side) */
    EV_GAP_OPEN = EV_GAP_CLOSE + MAX_STOP_SIDES, /* any phase: that of a side that pushes falls to 0 */
    N_EVENTS = EV_GAP_OPEN + MAX_STOP_SIDES
};

/* How an event's function g fires. With phi = sense * g, the event is phi
 * leaving its "before" set, phi < 0 (strict) or phi <= 0: so the strict and
 * non-strict inequalities of the contract ("turns positive", "falls from > 0
 * to 0", "below", "reaches") are each kept exactly. sense 0: a sign change
 * either way, the before set being the sign g had at the step's start.
 *
 * Most events read one state component: g = (s or 1) y[component] - offset,
 * cheap to evaluate, and on the dense output only that component is needed.
 * component -1: g is a function of the model (event_value). */
typedef struct event_rule {
    int sense;
    int strict;
    int terminal;
    int component;
    int times_pivot; /* the component is multiplied by the pivot s */
    double offset;
} event_rule;

static const event_rule EVENT_RULES[N_EVENTS] = {
    {+1, 0, 1, -1, 0, 0.0},                 /* EV_UPLIFT_A:       g <= 0  ->  g > 0 */
    {+1, 0, 1, -1, 0, 0.0},                 /* EV_UPLIFT_A_PRIME: g <= 0  ->  g > 0 */
    {-1, 0, 1, -1, 0, 0.0},                 /* EV_REST:           g >= 0  ->  g < 0 */
    {-1, 0, 1, -1, 0, 0.0},                 /* EV_SAFE:           g >= 0  ->  g < 0 */
    {-1, 1, 1, 0, 1, 0.0},                  /* EV_IMPACT:         g > 0   ->  g <= 0 (a start at theta = 0 is not "before") */
    {+1, 1, 1, 0, 1, HALF_PI},              /* EV_OVERTURN:       g < 0   ->  g >= 0 */
    {+1, 0, 0, -1, 0, 0.0},                 /* EV_CRITICAL:       g <= 0  ->  g > 0 */
    {0, 1, 0, NQ, 0, 0.0},                  /* EV_THETA_PEAK:     sign change */
    {0, 1, 0, NQ > 1 ? NQ + 1 : -1, 0, 0.0}, /* EV_X_PEAK:        sign change */
    {0, 1, 1, NQ > 1 ? NQ + 1 : -1, 0, 0.0}, /* EV_SETTLED:       sign change */
    {-1, 1, 1, -1, 0, 0.0},                 /* EV_SLIP:           g > 0   ->  g <= 0 */
    {-1, 1, 1, -1, 0, 0.0},                 /* EV_STOP:           g > 0   ->  g <= 0 */
    {-1, 1, 1, -1, 0, 0.0},                 /* EV_LIFT_OFF:       g > 0   ->  g <= 0 */
    {+1, 0, 1, -1, 0, 0.0},                 /* EV_SLIDE_UPLIFT_A: g <= 0  ->  g > 0 */
    {+1, 0, 1, -1, 0, 0.0},                 /* EV_SLIDE_UPLIFT_A_PRIME */
    {-1, 1, 1, NY + 2, 0, 0.0},             /* EV_LANDING_S:      g > 0   ->  g <= 0 (a start at v = 0 is not "before") */
    {-1, 1, 1, -1, 0, 0.0},                 /* EV_LANDING_O:      g > 0   ->  g <= 0 */
    {+1, 1, 1, -1, 0, 0.0},                 /* EV_FLIGHT_OVERTURN: g < 0  ->  g >= 0 */
    {-1, 1, 0, NY + 3, 0, 0.0},             /* EV_JUMP_S:         g > 0   ->  g <= 0 */
    {-1, 1, 0, -1, 0, 0.0},                 /* EV_JUMP_O:         g > 0   ->  g <= 0 */
    /* EV_GAP_CLOSE + i: g <= 0 -> g > 0, and EV_GAP_OPEN + i: g > 0 -> g <= 0; g the side's contact. */
    {+1, 0, 1, -1, 0, 0.0}, {+1, 0, 1, -1, 0, 0.0}, {+1, 0, 1, -1, 0, 0.0}, {+1, 0, 1, -1, 0, 0.0},
    {-1, 1, 1, -1, 0, 0.0}, {-1, 1, 1, -1, 0, 0.0}, {-1, 1, 1, -1, 0, 0.0}, {-1, 1, 1, -1, 0, 0.0}
};

/* The stop side an event follows, or -1. */
static int gap_side(int kind)
{
    if (kind >= EV_GAP_CLOSE && kind < N_EVENTS)
        return (kind - EV_GAP_CLOSE) % MAX_STOP_SIDES;
    return -1;
}

/* The penetration of stop side i (it depends on neither the pivot nor the regime). */
static double stop_gap(const constants *k, const double *y, int i)
{
    double gaps[MAX_STOP_SIDES] = {0.0};
    model_stop_gaps_prepared(y, 0.0, about(k, 1.0), gaps);
    return gaps[i];
}

/* The contact of every stop side, min(delta, k_b delta + c_b ddelta): a side's bumper
 * pushes while it is > 0 (a pad only pushes; neither pivot nor regime enters it). */
static void stop_contacts_at(const constants *k, const double *y, double *contacts)
{
    int i;
    for (i = MODEL_NSTOPS; i < MAX_STOP_SIDES; ++i)
        contacts[i] = 0.0;
    model_stop_contact_prepared(y, 0.0, about(k, 1.0), contacts);
}

/* The contact of stop side i (stop_contacts_at). */
static double stop_contact(const constants *k, const double *y, int i)
{
    double contacts[MAX_STOP_SIDES];
    stop_contacts_at(k, y, contacts);
    return contacts[i];
}

/* The regime of the state y: each stop side acts where its contact is > 0. */
static void stop_regime(const constants *k, const double *y, int *stop_on)
{
    int i;
    for (i = 0; i < MAX_STOP_SIDES; ++i)
        stop_on[i] = i < MODEL_NSTOPS && stop_contact(k, y, i) > 0.0;
}

static int is_before(double phi, int strict)
{
    return strict ? phi < 0.0 : phi <= 0.0;
}

/* normal_bound's constants, read per run (normal_bound_read): the weight m_t g [N], the damper's mass [kg], per
 * pivot (s = +1, -1) sum_i m_i (a_i, b_i) [kg m] and its length; ready 0: not read, or the model is not of their
 * form. */
typedef struct bound_constants {
    int ready;
    double weight, mass, a[2], b[2], rho[2];
    double floor; /* what normal_bound must exceed: 1e-6 of the weight (its rounding, and that of the N it bounds) */
} bound_constants;

/* What a run prepares from its parameters alone, kept from the last run of a batch: the cases of a study share
 * their block and damper. The constants about either pivot with every pad released (two model_prepare), E(0),
 * normal_bound's (six generated base reactions) and, without stops, the base's width in flight: about a
 * hundredth of a run. have 0: none yet. */
typedef struct memo_prepared {
    int have;
    double p[MODEL_NP];
    double about[2][NK];
    double energy_zero, base;
    bound_constants bound;
} memo_prepared;

/* The events' context: what their functions depend on besides (t, y). */
typedef struct event_ctx {
    ode *o;
    double energy_zero; /* E(0), the energy of the rest state */
    double energy_rest; /* the rest threshold on E(y) - E(0) */
    double energy_safe; /* below it the block can never uplift again; NaN: no bound (rule 4) */
    double mu_s;        /* the floor's static friction (inf: the contact never slips) */
    /* Per pivot (s = +1, -1), the least sliding base's uplift margin that is no rounding: SLIDE_UPLIFT_ROUNDING
     * times the weight's moment about the corner (mu_k = tan alpha keeps the margin at 0 while it slides). */
    double slide_uplift_floor[2];
    const double *theta_max, *x_max; /* the largest |y[0]|, |y[1]| so far (the run's results) */
    const double *u_max;             /* the largest |u| so far */
    bound_constants bound;
    /* The segment rocks on a stuck corner without a vertical component (normal_bound applies), about the pivot of
     * index bound_side (0: s = +1), whose rho is bound_rho. */
    int bound_live, bound_side;
    double bound_rho;
} event_ctx;

/* The factor of an event's component: the pivot s, or 1 (a product by 1 is exact). */
static double component_factor(const event_ctx *ec, const event_rule *e)
{
    return e->times_pivot ? (double)ec->o->phase : 1.0;
}

/* g of an event that reads one component, from that component's value. */
static inline double component_event(double factor, double offset, double v)
{
    return factor * v - offset;
}

/* g of EV_CRITICAL: s theta - s theta_cr_s(y). */
static double critical_event(const event_ctx *ec, const double *y, double ag)
{
    const double s = (double)ec->o->phase;
    return s * y[0] - s * model_critical_angle_prepared(y, ag, about(ec->o->k, s));
}

#ifdef MODEL_FRICTION
/* The floor's force on the block's contact at (t, y) in the segment's phase, (F, N) into fn: what the stuck
 * contact must hold, or the sliding one's -mu_slip N and N (phases.py, each phase's force). */
static void floor_force(ode *o, double t, const double *y, double *fn)
{
    const double ag = ode_ag(o, t), agy = ode_agy(o, t);
    if (o->sigma != 0) {
        double out[NQ + 2];
        slide_accel(o, t, y, out);
        fn[1] = out[NQ + 1];
        fn[0] = -o->mu_slip * fn[1];
    } else if (o->phase == 0) {
        model_contact_stick_force(1.0, y, ag, agy, o->k->p, friction_on(o), fn);
    } else {
        model_stick_force((double)o->phase, y, ag, agy, o->k->p, friction_on(o), fn);
    }
}
#endif

#ifdef MODEL_FRICTION
/* The floor's normal force N at (t, y) in the segment's phase, the lift-off event's g. Rocking with the pivot
 * stuck, from the generated base reaction, N_b = out + sum_j coeff_j ddq_j, with the accelerations f[NQ...] at
 * (t, y) when the caller has them (the FSAL derivative at a step's end, f = NULL: evaluated): the rocking
 * steps watch N at the cost of that one call. Else the phase's force (floor_force). */
static ALWAYS_INLINE double rocking_normal_force(ode *o, double t, const double *y, const double *f,
                                                 const double *cst)
{
    double out[3 * (NQ + 1)], n;
    int j;
    model_base_reaction_prepared(y, ode_ag(o, t), cst, out);
    n = out[NQ + 1];
    for (j = 0; j < NQ; ++j)
        n += out[NQ + 2 + j] * f[NQ + j];
    return n;
}

#ifdef MODEL_FLIGHT
/* A lower bound of the floor's N on a stuck corner without a vertical component, from the step's FSAL derivative f
 * at a few products' cost (the exact N costs the generated base reaction, its sin and cos: a sixth of a rocking
 * run's instructions). The whole system's vertical momentum: N = m_t g + sum_i m_i ddy_i, each body a point fixed
 * in the block frame at (a_i, b_i) from the pivot, ddy_i = a_i (ddtheta cos - dtheta^2 sin) - b_i (ddtheta sin +
 * dtheta^2 cos), and the damper's mass m moving along the block's x by q[1], + m (x (...) + ddx sin + 2 dx dtheta
 * cos); so N >= m_t g - (rho_s + m |x|) (|ddtheta| + dtheta^2) - m (|ddx| + 2 |dx dtheta|), rho_s = |sum_i m_i
 * (a_i, b_i)|. It proves N > 0 where it exceeds bound.floor (1e-6 of the weight); only where the segment's
 * bound_live says it applies. */
static ALWAYS_INLINE double normal_bound(const event_ctx *ec, const double *y, const double *f)
{
    const double w = y[NQ], spin = fabs(f[NQ]) + w * w;
#if NQ > 1
    const double x = fabs(y[1]), dx = fabs(y[NQ + 1]), ddx = fabs(f[NQ + 1]);
#else
    const double x = 0.0, dx = 0.0, ddx = 0.0;
#endif
    return ec->bound.weight - (ec->bound_rho + ec->bound.mass * x) * spin - ec->bound.mass * (ddx + 2.0 * dx * fabs(w));
}

/* normal_bound's second try, where |sin| <= 1 and |cos| <= 1 prove nothing (a strong pulse, a fast swing): N of
 * the same form is W + A cos(theta) + B sin(theta), with A = (a + m x) ddtheta - b dtheta^2 + 2 m dx dtheta and
 * B = m ddx - (a + m x) dtheta^2 - b ddtheta, and with |theta| = t, sin t in [t - t^3 / 6, t] and cos t in
 * [1 - t^2 / 2, 1 - t^2 / 2 + t^4 / 24] for every t >= 0 (Taylor's remainders), each term at its least end. A
 * few products more than normal_bound; the generated N costs its sin and cos. -inf where it proves nothing, within
 * 1e-6 of the weight, or 1e-9 of the terms (the rounding of their sum and of the generated N's). */
static NOINLINE double normal_bound_near(const event_ctx *ec, const double *y, const double *f)
{
    const double th = fabs(y[0]), th2 = th * th, w = y[NQ], ddt = f[NQ];
#if NQ > 1
    const double x = y[1], dx = y[NQ + 1], ddx = f[NQ + 1];
#else
    const double x = 0.0, dx = 0.0, ddx = 0.0;
#endif
    const double m = ec->bound.mass, a = ec->bound.a[ec->bound_side] + m * x, b = ec->bound.b[ec->bound_side];
    const double A = a * ddt - b * w * w + 2.0 * m * dx * w;
    const double B = (y[0] < 0.0 ? -1.0 : 1.0) * (m * ddx - a * w * w - b * ddt); /* times sin |theta| */
    const double th4 = th2 * th2, cos_hi = 1.0 - 0.5 * th2 + th4 / 24.0, cos_lo = cos_hi - th4 * th2 / 720.0;
    const double sin_lo = th - th * th2 / 6.0, sin_hi = sin_lo + th * th4 / 120.0;
    const double bound = ec->bound.weight + A * (A >= 0.0 ? cos_lo : cos_hi) + B * (B >= 0.0 ? sin_lo : sin_hi);
    return bound > 1e-6 * ec->bound.weight + 1e-9 * (fabs(A) + fabs(B)) ? bound : -INFINITY;
}

/* N_b of the generated base reaction about s at y with the accelerations dd (NQ values), no vertical component. */
static double normal_at(const constants *k, double s, const double *y, const double *dd)
{
    double out[3 * (NQ + 1)], n;
    int j;
    model_base_reaction_prepared(y, 0.0, about(k, s), out);
    n = out[NQ + 1];
    for (j = 0; j < NQ; ++j)
        n += out[NQ + 2 + j] * dd[j];
    return n;
}

/* normal_bound's constants from the generated base reaction (the weight at rest; per pivot, at theta = 0 and
 * dtheta = 1, the moment sum_i m_i b_i from the dtheta^2 term and sum_i m_i a_i from ddtheta's coefficient; the
 * damper's mass from ddx's coefficient at theta = pi/2), then the form checked on a state of every kind of term
 * about each pivot: where the generated N differs from it by more than rounding (a model of another form) the
 * bound stays off. */
static void normal_bound_read(bound_constants *b, const constants *k)
{
    static const double trial[2][2 * NQ + NQ] = {
#if NQ > 1
        {0.31, 0.12, -1.7, 0.9, 2.3, -1.1},
        {-0.83, -0.27, 0.6, -2.2, -0.4, 3.1},
#else
        {0.31, -1.7, 2.3},
        {-0.83, 0.6, -0.4},
#endif
    };
    double y[NY] = {0.0}, dd[NQ] = {0.0}, out[3 * (NQ + 1)];
    int i, ok = 1;
    b->weight = normal_at(k, 1.0, y, dd);
    b->mass = 0.0;
#if NQ > 1
    y[0] = PI / 2.0;
    model_base_reaction_prepared(y, 0.0, about(k, 1.0), out);
    b->mass = out[NQ + 3];
    y[0] = 0.0;
#endif
    for (i = 0; i < 2; ++i) {
        y[NQ] = 1.0;
        model_base_reaction_prepared(y, 0.0, about(k, i == 0 ? 1.0 : -1.0), out);
        b->a[i] = out[NQ + 2];
        b->b[i] = b->weight - out[NQ + 1];
        y[NQ] = 0.0;
        b->rho[i] = sqrt(b->a[i] * b->a[i] + b->b[i] * b->b[i]);
    }
    for (i = 0; i < 2 && ok; ++i) { /* a state per pivot */
        const double *v = trial[i];
        const double th = v[0], c = cos(th), sn = sin(th), w = v[NQ], ddt = v[2 * NQ];
        double expect, got, x = 0.0, dx = 0.0, ddx = 0.0;
        int j;
        for (j = 0; j < NY; ++j)
            y[j] = v[j];
        for (j = 0; j < NQ; ++j)
            dd[j] = v[NY + j];
#if NQ > 1
        x = v[1], dx = v[NQ + 1], ddx = v[2 * NQ + 1];
#endif
        expect = b->weight + (b->a[i] + b->mass * x) * (ddt * c - w * w * sn) - b->b[i] * (ddt * sn + w * w * c) +
                 b->mass * (ddx * sn + 2.0 * dx * w * c);
        got = normal_at(k, i == 0 ? 1.0 : -1.0, y, dd);
        ok = isfinite(got) && fabs(got - expect) <= 1e-9 * (fabs(b->weight) + 10.0 * (b->rho[i] + b->mass));
    }
    b->ready = ok && b->weight > 0.0 && isfinite(b->rho[0]) && isfinite(b->rho[1]);
    b->floor = 1e-6 * b->weight;
}

#endif

/* The lift-off event's g on a stuck corner from its N = n: on a floor without friction (mu_s = inf) N can reach
 * 0 while the floor holds a tangential force, and letting go of it may drive the corner into the floor: the
 * block takes off where N <= 0 and the free flight lifts the corner, the larger of N and minus the corner's
 * vertical acceleration in flight falling to 0 (numpy_backend's takeoff_margin; docs/simulation.md, "Flight").
 * The flight's acceleration only where N <= 0. */
static double lift_off_margin(const event_ctx *ec, double t, const double *y, double n)
{
#ifdef MODEL_FLIGHT
    ode *o = ec->o;
    double out[NQ + 2];
    if (n > 0.0 || isfinite(ec->mu_s))
        return n;
    model_flight_accel((double)o->phase, y, ode_ag(o, t), ode_agy(o, t), o->k->p, friction_on(o), out);
    return max2(n, -out[NQ + 1]);
#else
    (void)ec, (void)t, (void)y;
    return n;
#endif
}

static double lift_off_value(const event_ctx *ec, double t, const double *y, const double *f)
{
    ode *o = ec->o;
    double fn[2];
    if (o->phase != 0 && o->sigma == 0) {
        double at_gravity[NK], dy[NA];
        if (f == NULL) {
            ode_rhs(o, t, y, dy);
            f = dy;
        }
        return lift_off_margin(ec, t, y, rocking_normal_force(o, t, y, f, gravity_constants(o, (double)o->phase, t, at_gravity)));
    }
    floor_force(o, t, y, fn);
    return fn[1];
}

/* The lift-off event's g at a step's end or a segment's start, f the derivative there: a bound of N where one
 * proves N > 0 (normal_bound, normal_bound_near: its sign is all the detection reads, and a root is located with
 * exact values), else lift_off_value. */
static ALWAYS_INLINE double lift_off_at_end(const event_ctx *ec, double t, const double *y, const double *f)
{
#ifdef MODEL_FLIGHT
    if (ec->bound_live) {
        double n = normal_bound(ec, y, f);
        if (n > ec->bound.floor || (n = normal_bound_near(ec, y, f)) > 0.0)
            return n;
    }
#endif
    return lift_off_value(ec, t, y, f);
}
#endif

#ifdef MODEL_FLIGHT
/* The other corner's height above the floor in flight (generated corner_heights). */
static double corner_height_other(const event_ctx *ec, double t, const double *y)
{
    double h[2];
    model_corner_heights((double)ec->o->phase, y, ode_ag(ec->o, t), ode_agy(ec->o, t), ec->o->k->p,
                         friction_on(ec->o), y[NY + 2], h);
    return h[1];
}

/* The other corner's vertical rate in flight (generated flight_corner). */
static double corner_rate_other(const event_ctx *ec, double t, const double *y)
{
    double c[4];
    model_flight_corner((double)ec->o->phase, y, ode_ag(ec->o, t), ode_agy(ec->o, t), ec->o->k->p,
                        friction_on(ec->o), y[NY], y[NY + 2], y[NY + 1], y[NY + 3], c);
    return c[3];
}
#endif

/* The uplift function about s at (t, y). */
static inline double uplift_event(const event_ctx *ec, double s, double t, const double *y)
{
    double at_gravity[NK];
    return model_uplift_prepared(y, ode_ag(ec->o, t), gravity_constants(ec->o, s, t, at_gravity));
}

#ifdef MODEL_FRICTION
/* The uplift function about s at (t, y) of a sliding base, written with its friction force, less the rounding
 * of the weight's moment (ec->slide_uplift_floor, as numpy_backend's). */
static double slide_uplift_event(const event_ctx *ec, double s, double t, const double *y)
{
    return model_slide_uplift(s, y, ode_ag(ec->o, t), ode_agy(ec->o, t), ec->o->k->p, friction_on(ec->o),
                              ec->o->mu_slip) -
           ec->slide_uplift_floor[s < 0.0];
}
#endif

/* g of an event that is a function of the model. */
static double model_event(const event_ctx *ec, int kind, double t, const double *y)
{
#ifdef MODEL_FRICTION
    double fn[2];
#endif
    switch (kind) {
    case EV_UPLIFT_A:
        return uplift_event(ec, 1.0, t, y);
    case EV_UPLIFT_A_PRIME:
        return uplift_event(ec, -1.0, t, y);
#ifdef MODEL_FRICTION
    case EV_SLIP:
        floor_force(ec->o, t, y, fn);
        return ec->mu_s * fn[1] - fabs(fn[0]);
    case EV_STOP:
        return ec->o->sigma * y[NY + 1];
    case EV_SLIDE_UPLIFT_A:
        return slide_uplift_event(ec, 1.0, t, y);
    case EV_SLIDE_UPLIFT_A_PRIME:
        return slide_uplift_event(ec, -1.0, t, y);
    case EV_LIFT_OFF:
        return lift_off_value(ec, t, y, NULL);
#endif
#ifdef MODEL_FLIGHT
    case EV_LANDING_O:
        return corner_height_other(ec, t, y);
    case EV_FLIGHT_OVERTURN:
        return fabs(y[0]) - HALF_PI;
    case EV_JUMP_O:
        return corner_rate_other(ec, t, y);
#endif
    case EV_REST:
        /* In full contact the energy does not depend on the pivot. */
        return (model_energy_prepared(y, 0.0, about(ec->o->k, 1.0)) - ec->energy_zero) - ec->energy_rest;
    case EV_SAFE:
        return (model_energy_prepared(y, 0.0, about(ec->o->k, 1.0)) - ec->energy_zero) - ec->energy_safe;
    case EV_CRITICAL:
        return critical_event(ec, y, ode_ag(ec->o, t));
    default:
        if (gap_side(kind) >= 0)
            return stop_contact(ec->o->k, y, gap_side(kind));
        return 0.0; /* not reached: the other events read one component */
    }
}

/* EV_CRITICAL's g = s theta - atan(z), z = s tan(theta_cr), or an upper
 * bound of it that is < 0: atan(z) >= z / (1 + z) for z >= 0 (equal at 0, and
 * the derivatives are 1 / (1 + z^2) >= 1 / (1 + z)^2). Narrowed by 4 eps,
 * relative and absolute: the tangent and the angle are generated separately,
 * each right to a few ulps of its terms, which may cancel. Most steps are far
 * below the critical angle: no atan2 there. A NaN tangent (the weights'
 * centre not above the ground) fails the test. */
static ALWAYS_INLINE double critical_event_bound(const event_ctx *ec, double t, const double *y)
{
    const double s = (double)ec->o->phase, ag = ode_ag(ec->o, t);
    const double z = s * model_critical_tangent_prepared(y, ag, about(ec->o->k, s));
    const double below = z / (1.0 + z) - 4.0 * DBL_EPSILON * (1.0 + z);
    if (z >= 0.0 && s * y[0] < below)
        return s * y[0] - below;
    return critical_event(ec, y, ag);
}

/* g at a step's end: exact, except that a value known to be < 0 may be a
 * bound (critical_event_bound); locating an event uses exact values only. */
static ALWAYS_INLINE double event_value(const event_ctx *ec, int kind, double t, const double *y, const double *f)
{
    const event_rule *e = &EVENT_RULES[kind];
    if (e->component >= 0)
        return component_event(component_factor(ec, e), e->offset, y[e->component]);
#ifdef MODEL_FRICTION
    if (kind == EV_LIFT_OFF)
        return lift_off_at_end(ec, t, y, f);
#else
    (void)f;
#endif
    return SHORTCUTS && kind == EV_CRITICAL ? critical_event_bound(ec, t, y) : model_event(ec, kind, t, y);
}

/* The event function on the dense output of the last step. */
static double event_on_dense(const event_ctx *ec, dopri *d, int kind, double t)
{
    const event_rule *e = &EVENT_RULES[kind];
    double y[NA];
    if (e->component >= 0)
        return component_event(component_factor(ec, e), e->offset, dopri_dense1(d, t, e->component));
    dopri_dense(d, t, y);
    return model_event(ec, kind, t, y);
}

/* The sense over a step that starts with g = g_old of an event of rule sense. */
static int event_sense(int sense, double g_old)
{
    return sense ? sense : (g_old > 0.0 ? -1 : +1);
}

/* Locate a stop side's event (gap_side(kind) >= 0) as locate_event does. Its contact min(delta, k_b delta +
 * c_b ddelta) has a kink between slopes up to k_b / c_b times apart on the side "before" its root; past the root it
 * is the smooth branch that crosses 0 (delta for a closing, the bracket for a release). A regula falsi across the
 * kink creeps from the flat branch: Illinois alone took 26 trials to locate a closing and 72 a release (100
 * responses of bench/stops_map.py stops), and with a bisection after each trial that kept more than half the
 * bracket 14 and 32 on average (400 responses: -n 20; these trials, 7 and 9). So the trials interpolate the points "after" the root, on its branch: inversely quadratic through
 * the last three, else the secant through the last two, else (the first trial: only the step's end is after it)
 * the bisection. An interpolation that falls before the root lands near it: the next trial is LOCATE_NUDGE of the
 * bracket past it; one that falls before again, the regula falsi between the ends; then the bisection. A trial is
 * kept half the tolerance away from both ends: once the after side has converged, the next trial lands just across
 * the root and closes the bracket. */
#define LOCATE_NUDGE (1.0 / 16.0)

/* Stop side i's contact on the dense output of the last step (event_on_dense for its events: that one stays
 * inlined in locate_event alone). */
static double contact_on_dense(const event_ctx *ec, dopri *d, int i, double t)
{
    double y[NA];
    dopri_dense(d, t, y);
    return stop_contact(ec->o->k, y, i);
}

static double locate_kinked(const event_ctx *ec, dopri *d, int kind, int sense, double ta, double phi_a, double tb,
                            double phi_b)
{
    enum { BISECT, INTERPOLATE, NUDGE, FALSI } how = BISECT; /* the next trial */
    const int strict = EVENT_RULES[kind].strict;
    const double tol = 4.0 * DBL_EPSILON * max2(fabs(ta), fabs(tb));
    double t_prev = tb, phi_prev = phi_b; /* the point "after" before tb (none yet: tb itself) */
    double t_prev2 = tb, phi_prev2 = phi_b; /* and the one before it */
    int iter;
    for (iter = 0; iter < 200 && tb - ta > tol; ++iter) {
        double tc, phi_c;
        if (how == INTERPOLATE && phi_prev2 != phi_prev && phi_prev2 != phi_b && phi_b != phi_prev)
            tc = t_prev2 * (phi_prev * phi_b) / ((phi_prev2 - phi_prev) * (phi_prev2 - phi_b)) +
                 t_prev * (phi_prev2 * phi_b) / ((phi_prev - phi_prev2) * (phi_prev - phi_b)) +
                 tb * (phi_prev2 * phi_prev) / ((phi_b - phi_prev2) * (phi_b - phi_prev));
        else if (how == INTERPOLATE && phi_b != phi_prev)
            tc = tb - phi_b * ((tb - t_prev) / (phi_b - phi_prev));
        else if (how == FALSI && phi_b != phi_a)
            tc = tb - phi_b * ((tb - ta) / (phi_b - phi_a));
        else if (how == NUDGE)
            tc = ta + LOCATE_NUDGE * (tb - ta);
        else
            tc = ta + 0.5 * (tb - ta);
        tc = min2(max2(tc, ta + 0.5 * tol), tb - 0.5 * tol); /* a NaN becomes the lower limit */
        if (!(tc > ta && tc < tb)) /* NaN, or rounding at the ends */
            tc = ta + 0.5 * (tb - ta);
        if (!(tc > ta && tc < tb)) /* no double left between the ends */
            break;
        phi_c = sense * contact_on_dense(ec, d, gap_side(kind), tc);
        if (is_before(phi_c, strict)) {
            ta = tc;
            phi_a = phi_c;
            how = how == INTERPOLATE ? NUDGE : how == NUDGE ? FALSI : how == FALSI ? BISECT : FALSI;
        } else {
            /* An interpolation that did not halve |phi| there has left the branch's smooth part: bisect. */
            how = how == INTERPOLATE && fabs(phi_c) > 0.5 * fabs(phi_b) ? BISECT : INTERPOLATE;
            t_prev2 = t_prev;
            phi_prev2 = phi_prev;
            t_prev = tb;
            phi_prev = phi_b;
            tb = tc;
            phi_b = phi_c;
        }
    }
    return tb;
}

/* Locate an event that fired in the last step: phi = sense g is "before" at ta
 * and not at tb. Illinois: regula falsi that halves the value kept at an end
 * that survived twice, so that both ends converge. A trial point is kept at
 * least half the tolerance away from both ends: once one end has converged,
 * the next trial lands just across the root and closes the bracket (plain
 * regula falsi would creep towards it from one side). Bisection only as a
 * safety net; a stop side's event has its own trials (locate_kinked). Returns the end of the final bracket on the
 * "after" side, so that the event has happened at the returned time;
 * |dt| <= 4 eps t. */
static double locate_event(const event_ctx *ec, dopri *d, int kind, int sense, double ta, double phi_a, double tb,
                           double phi_b)
{
    const int strict = EVENT_RULES[kind].strict;
    const double tol = 4.0 * DBL_EPSILON * max2(fabs(ta), fabs(tb));
    int kept = 0; /* +1: ta moved last time (tb kept), -1: tb moved */
    int iter;
    if (gap_side(kind) >= 0)
        return locate_kinked(ec, d, kind, sense, ta, phi_a, tb, phi_b);
    for (iter = 0; iter < 200 && tb - ta > tol; ++iter) {
        double tc, phi_c;
        if (iter < 40 && phi_b != phi_a) {
            tc = tb - phi_b * ((tb - ta) / (phi_b - phi_a));
            tc = min2(max2(tc, ta + 0.5 * tol), tb - 0.5 * tol); /* a NaN becomes the lower limit */
        } else {
            tc = ta + 0.5 * (tb - ta);
        }
        if (!(tc > ta && tc < tb)) /* NaN, or rounding at the ends */
            tc = ta + 0.5 * (tb - ta);
        if (!(tc > ta && tc < tb)) /* no double left between the ends */
            break;
        phi_c = sense * event_on_dense(ec, d, kind, tc);
        if (is_before(phi_c, strict)) {
            ta = tc;
            phi_a = phi_c;
            if (kept == +1)
                phi_b *= 0.5;
            kept = +1;
        } else {
            tb = tc;
            phi_b = phi_c;
            if (kept == -1)
                phi_a *= 0.5;
            kept = -1;
        }
    }
    return tb;
}

/* An event watched during one segment, its rule read once for the segment:
 * the per-step scan then reads no table and makes no call for an event of one
 * component. sense 0 as in event_rule. */
typedef struct watched {
    int kind, sense, strict, component;
    double factor, offset; /* g = factor y[component] - offset (component_event) */
} watched;

/* The events watched during one segment, with their values at the last step end. */
typedef struct event_set {
    int n;
    watched w[N_EVENTS]; /* in enum order (ties go to the first) */
    double g[N_EVENTS];  /* g of w[i] */
    int have_contacts;   /* contacts holds every stop side's contact at the last step end (the segment's start first) */
    double contacts[MAX_STOP_SIDES];
    int lift_last; /* the last event watched is the lift-off, and normal_bound applies (events_scan's first test) */
} event_set;

/* What the events of one accepted step found. */
typedef struct step_events {
    int terminal;       /* the earliest terminal event, or -1 */
    double t_stop;      /* its time, or the step's end */
    int n_passed, passed[N_EVENTS]; /* non-terminal events located at or before t_stop */
    double t_root[N_EVENTS];        /* by kind */
} step_events;

/* A set of event kinds, one bit each. */
typedef uint32_t event_mask;
#if N_EVENTS > 32
#error "more event kinds than an event_mask holds"
#endif

/* The least kind in a non-empty set. */
static inline int first_event(event_mask m)
{
#if defined(__GNUC__) || defined(__clang__)
    return __builtin_ctz(m);
#else
    int k = 0;
    while (!(m >> k & 1u))
        ++k;
    return k;
#endif
}

/* The index in an event_set started from the set m (events_start) of its event kind. */
static inline int event_index(event_mask m, int kind)
{
    m &= ((event_mask)1 << kind) - 1u;
#if defined(__GNUC__) || defined(__clang__)
    return __builtin_popcount(m);
#else
    int n = 0;
    for (; m != 0; m &= m - 1)
        ++n;
    return n;
#endif
}

/* Watch the events of the set `active`, in enum order, from (t, y), f the derivative there. */
static void events_start(event_set *es, const event_ctx *ec, event_mask active, double t, const double *y,
                         const double *f)
{
    es->n = 0;
    es->have_contacts = 0;
    for (; active != 0; active &= active - 1) {
        const int k = first_event(active);
        const event_rule *e = &EVENT_RULES[k];
        watched *w = &es->w[es->n];
        w->kind = k;
        w->sense = e->sense;
        w->strict = e->strict;
        w->component = e->component;
        w->factor = component_factor(ec, e);
        w->offset = e->offset;
        if (gap_side(k) >= 0) { /* every side's contact from one call, as in events_scan */
            if (!es->have_contacts)
                stop_contacts_at(ec->o->k, y, es->contacts);
            es->have_contacts = 1;
            es->g[es->n++] = es->contacts[gap_side(k)];
        } else {
            es->g[es->n++] = event_value(ec, k, t, y, f);
        }
    }
    es->lift_last = FLIGHT && es->n > 0 && es->w[es->n - 1].kind == EV_LIFT_OFF && ec->bound_live;
}

/* Stop watching an event for the rest of the segment. */
static void events_drop(event_set *es, int kind)
{
    int i, j = 0;
    for (i = 0; i < es->n; ++i)
        if (es->w[i].kind != kind) {
            es->w[j] = es->w[i];
            es->g[j++] = es->g[i];
        }
    es->n = j;
    es->lift_last = es->lift_last && kind != EV_LIFT_OFF;
}

/* An extremum of theta or x inside the last step that cannot raise the
 * largest |theta| or |x| so far: not worth locating (the bound holds for the
 * whole step), and not reported. */
static int peak_below_max(const event_ctx *ec, const dopri *d, int kind)
{
    if (ec->o->flying) /* in flight every located point counts towards u_max and jump_max (see_flight) */
        return 0;
    if (kind == EV_THETA_PEAK)
        return dopri_dense_bound(d, 0) <= *ec->theta_max;
    if (kind == EV_X_PEAK)
        return NQ > 1 && dopri_dense_bound(d, 1) <= *ec->x_max;
    return 0;
}

/* Check every watched event over the step just accepted: detection from the
 * values at both ends, location on the dense output, the earliest terminal
 * event wins and the non-terminal ones after it are dropped. */
static ALWAYS_INLINE void events_scan(event_set *es, const event_ctx *ec, dopri *d, step_events *out)
{
    int fired[N_EVENTS];
    int n = es->n;
    int i, n_fired = 0;
    out->terminal = -1;
    out->t_stop = d->t;
    out->n_passed = 0;
    es->have_contacts = 0;
#ifdef MODEL_FLIGHT
    if (es->lift_last) { /* most steps: N's bound > 0 at both ends, no takeoff to test (the loop's rule, first) */
        const double g_new = normal_bound(ec, d->y, d->f);
        if (g_new > ec->bound.floor && es->g[n - 1] > 0.0) {
            es->g[n - 1] = g_new;
            --n;
        }
    }
#endif
    /* The values at the step's end become those at the next step's start; after
     * a terminal event the segment ends, and they are read no more. */
    for (i = 0; i < n; ++i) {
        const watched *w = &es->w[i];
        const int k = w->kind;
        double g_old = es->g[i], g_new;
        int sense;
        if (w->component >= 0) {
            g_new = component_event(w->factor, w->offset, d->y[w->component]);
        } else if (gap_side(k) >= 0) {
            /* The generated stop_contact gives every side at once: one call per step end. */
            if (!es->have_contacts)
                stop_contacts_at(ec->o->k, d->y, es->contacts);
            es->have_contacts = 1;
            g_new = es->contacts[gap_side(k)];
#ifdef MODEL_FRICTION
        } else if (k == EV_LIFT_OFF) {
            g_new = lift_off_at_end(ec, d->t, d->y, d->f);
#endif
        } else {
            g_new = event_value(ec, k, d->t, d->y, d->f);
        }
        es->g[i] = g_new;
        /* g keeps its strict sign over the step: neither sense can find its "before" at one end only (a product
         * that underflows to 0, or a NaN, goes on to the full test). */
        if (g_old * g_new > 0.0)
            continue;
        sense = event_sense(w->sense, g_old);
        if (!is_before(sense * g_old, w->strict) || is_before(sense * g_new, w->strict) ||
            (SHORTCUTS && peak_below_max(ec, d, k)))
            continue;
        fired[n_fired++] = k;
        /* The value at the step's start may be a bound (g_new is exact: a bound is only ever "before"); the
         * derivative there is the step's first stage. */
        if (k == EV_CRITICAL)
            g_old = model_event(ec, k, d->t_old, d->y_old);
#ifdef MODEL_FRICTION
        if (k == EV_LIFT_OFF)
            g_old = lift_off_value(ec, d->t_old, d->y_old, d->k[0]);
#endif
        out->t_root[k] = locate_event(ec, d, k, sense, d->t_old, sense * g_old, d->t, sense * g_new);
        if (EVENT_RULES[k].terminal && (out->terminal < 0 || out->t_root[k] < out->t_stop)) {
            out->terminal = k;
            out->t_stop = out->t_root[k];
        }
    }
    for (i = 0; i < n_fired; ++i) {
        const int k = fired[i];
        if (!EVENT_RULES[k].terminal && out->t_root[k] <= out->t_stop)
            out->passed[out->n_passed++] = k;
    }
}

/* ------------------------------------------------------------------------ */
/* 4. The phase machine                                                      */
/* ------------------------------------------------------------------------ */

/* The reference corner's height v in a flying state y (0 without flight). */
static double corner_height(const double *y)
{
#ifdef MODEL_FLIGHT
    return y[NY + 2];
#else
    (void)y;
    return 0.0;
#endif
}

/* The reference corner leaves the floor: v = 0 and dv > 0 (a bounce; a takeoff has dv = 0). */
static int corner_rising(const double *y)
{
#ifdef MODEL_FLIGHT
    return y[NY + 2] == 0.0 && y[NY + 3] > 0.0;
#else
    (void)y;
    return 0;
#endif
}

/* The height of the corner other than the reference one in a flying state y at t (0 without flight). */
static double corner_other_height(const event_ctx *ec, double t, const double *y)
{
#ifdef MODEL_FLIGHT
    return corner_height_other(ec, t, y);
#else
    (void)ec, (void)t, (void)y;
    return 0.0;
#endif
}

/* How a segment ended, besides an event (enum event_kind). */
enum {
    SEG_BOUND = -1,
    SEG_FAILED = -2,
    SEG_NO_LIFT = -3,
    SEG_MAX_STEPS = -4,
    SEG_STOPPED = -5,
    SEG_NO_SLIP = -6,
    SEG_NO_TAKEOFF = -7
};

#if NQ > 1
/* The arcs that cover the tilts [0, theta_m] (least_on_arcs), with the constants of their outer
 * corners: prepared once per theta_m, for every stroke a bound is taken at. */
typedef struct arcs {
    int n;
    double w;
    constants outer;
} arcs;
#endif

typedef struct run {
    const rocking_case *c;
    tolerance tol;
    ode o;
    event_ctx ec;
    dopri d;
    event_set events;
    double t, y[NA]; /* the state between segments */
    int phase;
    int sigma;      /* the contact: 0 stuck, +1 / -1 sliding with du of that sign (constant in a segment) */
    int flying;     /* in flight about the reference corner s = phase (0 sigma) */
    double t_takeoff; /* when the current flight started */
    int lift_phase, lift_sigma; /* the phase the current flight took off from: s, sigma */
    int skip_lift_check; /* the next segment does not check N <= 0 at its start (a grazing takeoff) */
    double base;    /* the base width B [m], from corner_heights (the bounce speed of a landing) */
    int friction;   /* the floor's mu_s is finite: the events of friction are watched (phases.py) */
    double atol[NA]; /* the case's, then those of u and du (simulate_one) */
    unsigned exits[PHASE_COUNT]; /* phase_exit_events of each phase */
    int codes[2][2];             /* phase_of each pair of constraints */
    double t_start; /* when the current rocking phase started, at theta = 0 */
    double h_first; /* first step of the next segment; 0: Hairer's heuristic */
    int early;  /* the early rest of rule 4 applies: early_rest and a positive uplift energy */
    constants *k; /* of the parameters, in the current regime of the stops (r->o.k too) */
    regime_store regimes; /* the constants of the regimes met in the run (constants_switch) */
    int safe;   /* in full contact after the pulse below the uplift energy: settling */
    int verdict; /* the early verdict of rule 4 applies: early_verdict and derived bounds */
    double bound_at[2], bound;     /* the last bound of the early verdict, and the (theta_max, x_max) it is for */
    /* The parts of that bound set by theta_max alone, kept while only x_max grows, and the theta_max
     * each is for: least_at_tilt, the arcs. */
    double least_tilt_at, least_tilt;
#if NQ > 1
    double arcs_at;
    arcs tilts;
    double least_stroke_at, least_stroke; /* verdict_refuted's least at the stroke x_max upright, and its x_max */
#endif
    rocking_result *res;
    const volatile int32_t *stop;  /* the caller's stop flag, or NULL */
    const int32_t *velocity_law;   /* NQ flags: 1 for the velocity impact law; NULL: momentum everywhere */
    int64_t samples;               /* recorded history samples (rule 5: they count as work) */
    /* history */
    rocking_history *hist;
    int64_t n_rec;
    double last_t, last_y[NA];
    int last_phase, last_sigma, last_flying;
    double next_sample; /* index of the next record_dt multiple to sample */
} run;

#ifdef MODEL_FRICTION
/* The ode of the run's phase at t outside a segment (a check at its start, a guard at its end, a sample's
 * force): the pulse acts before t_p, as at the start of a segment. */
static void ode_at(const run *r, double t, ode *o)
{
    *o = r->o;
    o->phase = r->phase;
    o->sigma = r->sigma;
    o->flying = r->flying;
    o->mu_slip = r->c->mu_k * r->sigma;
    o->pulse_on = t < r->c->t_p;
    o->vertical = o->pulse_on && r->c->a_v != 0.0;
    o->piece = r->c->motion == ROCKING_MOTION_SAMPLED ? pulse_piece(r->c, t) : 0.0;
    o->memo_t = NAN;
    o->cst = about(r->k, (double)r->phase);
    regime_inputs(r->k, o->on);
}

/* The floor's force (F, N) on the contact at (t, y) in the run's phase (floor_force), outside a segment. */
static void floor_force_at(const run *r, double t, const double *y, double *fn)
{
    ode o;
    ode_at(r, t, &o);
    floor_force(&o, t, y, fn);
}
#endif

/* The floor's columns of a history sample: u, du, N, F. */
static void record_floor(const run *r, double t, const double *y, double *out)
{
#ifdef MODEL_FRICTION
    double fn[2] = {0.0, 0.0}; /* in flight the floor holds nothing */
    if (!r->flying)
        floor_force_at(r, t, y, fn);
    out[0] = y[NY];
    out[1] = y[NY + 1];
    out[2] = fn[1];
    out[3] = fn[0];
#else
    (void)r, (void)t, (void)y;
    out[0] = out[1] = out[2] = out[3] = 0.0;
#endif
}

/* The flight's columns of a history sample: the reference corner's height v, its rate dv, and 1 in flight. */
static void record_flight(const run *r, const double *y, double *out)
{
#ifdef MODEL_FLIGHT
    out[0] = y[NY + 2];
    out[1] = y[NY + 3];
#else
    (void)y;
    out[0] = out[1] = 0.0;
#endif
    out[2] = r->flying ? 1.0 : 0.0;
}

/* Append a history sample, unless it repeats the last one exactly (a segment
 * restarting where the previous one ended). Counts past the capacity. */
static void record(run *r, double t, const double *y, int phase)
{
    rocking_history *h = r->hist;
    int i, same;
    if (h == NULL)
        return;
    same = r->n_rec > 0 && t == r->last_t && phase == r->last_phase && r->sigma == r->last_sigma &&
           r->flying == r->last_flying;
    for (i = 0; same && i < NA; ++i)
        same = y[i] == r->last_y[i];
    if (same)
        return;
    if (r->n_rec < h->capacity) {
        h->t[r->n_rec] = t;
        memcpy(h->y + r->n_rec * NY, y, NY * sizeof *y);
        h->phase[r->n_rec] = phase;
        h->ag[r->n_rec] = pulse_at(r->c, t);
        if (h->floor != NULL)
            record_floor(r, t, y, h->floor + 4 * r->n_rec);
        if (h->slide != NULL)
            h->slide[r->n_rec] = r->sigma;
        if (h->flight != NULL)
            record_flight(r, y, h->flight + 3 * r->n_rec);
    }
    ++r->n_rec;
    r->last_t = t;
    memcpy(r->last_y, y, sizeof r->last_y);
    r->last_phase = phase;
    r->last_sigma = r->sigma;
    r->last_flying = r->flying;
}

/* The least index k >= 0 whose sample time k dt is > t (history.py's
 * first_sample_after). Every sample time is the product k dt rounded once,
 * monotone in k; floor(t / dt) rounds the ratio too and may land one index off
 * either way (t / dt rounded up to k exactly where k dt > t skipped sample k):
 * corrected both ways on the products themselves. */
static double record_first_sample(double t, double dt)
{
    double k = fmax(floor(t / dt) + 1.0, 0.0);
    while (k > 0.0 && (k - 1.0) * dt > t)
        k -= 1.0;
    while (k * dt <= t)
        k += 1.0;
    return k;
}

/* Samples at the multiples of record_dt in [t_old, t_stop), strictly after
 * the segment's start (next_sample was set past it) and strictly before its
 * end (the end is recorded as an event sample). */
/* The work of the run so far has passed max_steps (rule 5). */
static int over_budget(const run *r)
{
    return r->d.evaluations + r->samples > r->c->max_steps;
}

static void record_samples(run *r, double t_stop)
{
    const double dt = r->c->record_dt;
    double y[NA];
    if (r->hist == NULL || !(dt > 0.0))
        return;
    memcpy(y, r->d.y, sizeof y); /* the components not integrated */
    for (;;) {
        const double t = r->next_sample * dt;
        if (!(t < t_stop) || over_budget(r)) /* past the budget the segment is undone anyway */
            break;
        dopri_dense(&r->d, t, y);
        record(r, t, y, r->phase);
        r->samples += 1;
        r->next_sample += 1.0;
    }
}

#if MODEL_NSTOPS > 0
/* No stop side pushes at the last step's end (its contact <= 0, read by events_scan): every
 * bumper force there is 0, and bumper_force_max stays. */
static int pads_apart(const event_set *es)
{
    int i;
    if (!es->have_contacts)
        return 0;
    for (i = 0; i < MODEL_NSTOPS; ++i)
        if (es->contacts[i] > 0.0)
            return 0;
    return 1;
}
#endif

#if MODEL_NSTOPS > 0
/* The largest force of any bumper at the state y (a pad's force from its state and memory). */
static double bumper_force(const run *r, const double *y)
{
    double forces[MODEL_NSTOPS], f = 0.0;
    int i;
    model_stop_forces_prepared(y, 0.0, about(r->o.k, 1.0), forces);
    for (i = 0; i < MODEL_NSTOPS; ++i)
        f = max2(f, forces[i]);
    return f;
}

/* bumper_force on the last step's dense output at t_old + x (t_end - t_old). */
static double bumper_force_in_step(run *r, double t_end, double x)
{
    double y[NA];
    dopri_dense(&r->d, r->d.t_old + x * (t_end - r->d.t_old), y);
    return bumper_force(r, y);
}

/* Where a step's dense output is looked at for the peak of a bumper's force: its ends and middle, then where the
 * peak is searched for its quarters too (numpy_backend.PEAK_SAMPLES, PEAK_QUARTERS). A Hunt-Crossley pad's
 * search for it narrows its bracket to PEAK_WIDTH of the step, the Newton iteration on a Kelvin-Voigt pad's
 * quartic stops at PEAK_ROOT_WIDTH (numpy_backend.step_peak). */
#define PEAK_POINTS 3
#define PEAK_WIDTH 1e-5
#define PEAK_ROOT_WIDTH 1e-9

/* Every pad Kelvin-Voigt (no Hunt-Crossley memory in the regime): the pads' force is affine in the state. */
#if MODEL_NREGIME > MODEL_NSTOPS
#define PADS_AFFINE 0
#else
#define PADS_AFFINE 1
#endif

#if PADS_AFFINE
/* The derivative of the quartic c[0] + c[1] s + ... + c[4] s^4 at s (d = 1) or its second derivative (d = 2). */
static double quartic_slope(const double *c, double s, int d)
{
    if (d == 2)
        return 2.0 * c[2] + s * (6.0 * c[3] + s * 12.0 * c[4]);
    return c[1] + s * (2.0 * c[2] + s * (3.0 * c[3] + s * 4.0 * c[4]));
}

/* The root of the quartic's derivative in [lo, hi] where it falls through 0 (> 0 at lo, < 0 at hi, monotone
 * between): Newton's iteration kept inside the shrinking bracket, bisection where it leaves it, to PEAK_ROOT_WIDTH. */
static double quartic_crest(const double *c, double lo, double hi)
{
    double s = 0.5 * (lo + hi), next, slope;
    int i;
    for (i = 0; i < 64; ++i) {
        slope = quartic_slope(c, s, 1);
        if (slope > 0.0)
            lo = s;
        else if (slope < 0.0)
            hi = s;
        else
            return s;
        next = s - slope / quartic_slope(c, s, 2);
        if (!(next > lo && next < hi)) /* NaN too */
            next = 0.5 * (lo + hi);
        if (fabs(next - s) < PEAK_ROOT_WIDTH || hi - lo < PEAK_ROOT_WIDTH)
            return next;
        s = next;
    }
    return s;
}

/* Where in [0, 1] the quartic through f at x = 0, 1/4, 1/2, 3/4, 1 is largest: at a crest (a root of its cubic
 * derivative where that falls through 0; the derivative is monotone between the roots of the quadratic second
 * derivative), or at an end. The same operations as numpy_backend.quartic_peak. */
static double quartic_peak(const double *f)
{
    /* The quartic in s = 2 x - 1 on the nodes -1, -1/2, 0, 1/2, 1: its even and odd parts. */
    const double far = 0.5 * (f[0] + f[4]), near = 0.5 * (f[1] + f[3]);
    const double rise = 0.5 * (f[4] - f[0]), step = 0.5 * (f[3] - f[1]);
    double c[5], cuts[4], best_s = -1.0, best, a, b, q, root, value;
    int n = 0, i;
    c[0] = f[2];
    c[4] = (4.0 / 3.0) * (far - 4.0 * near + 3.0 * f[2]);
    c[2] = far - f[2] - c[4];
    c[3] = (4.0 / 3.0) * (rise - 2.0 * step);
    c[1] = rise - c[3];
    best = f[0];
    if (f[4] > best)
        best_s = 1.0, best = f[4];
    /* The roots of the second derivative 12 c4 s^2 + 6 c3 s + 2 c2 in (-1, 1) cut [-1, 1] where the slope turns. */
    cuts[n++] = -1.0;
    a = 6.0 * c[4], b = 3.0 * c[3];
    q = b * b - 4.0 * a * c[2];
    if (a != 0.0 && q >= 0.0) {
        const double r = -0.5 * (b + copysign(sqrt(q), b));
        const double one = r != 0.0 ? c[2] / r : 0.0, two = r / a;
        const double lo = fmin(one, two), hi = fmax(one, two);
        if (lo > -1.0 && lo < 1.0)
            cuts[n++] = lo;
        if (hi > -1.0 && hi < 1.0 && hi != lo)
            cuts[n++] = hi;
    } else if (a == 0.0 && b != 0.0 && -c[2] / b > -1.0 && -c[2] / b < 1.0) {
        cuts[n++] = -c[2] / b;
    }
    cuts[n++] = 1.0;
    for (i = 0; i + 1 < n; ++i) {
        if (!(quartic_slope(c, cuts[i], 1) > 0.0 && quartic_slope(c, cuts[i + 1], 1) < 0.0))
            continue;
        root = quartic_crest(c, cuts[i], cuts[i + 1]);
        value = c[0] + root * (c[1] + root * (c[2] + root * (c[3] + root * c[4])));
        if (value > best)
            best_s = root, best = value;
    }
    return 0.5 * (best_s + 1.0);
}
#endif

#if !PADS_AFFINE
/* The largest bumper force on the last step's dense output up to t_end over the step fractions [a, b], which
 * bracket a crest: Brent's search for a minimum (Brent 1973, "localmin") on the force's negative, a parabola
 * through the three best points where it falls well inside the bracket, else a golden section of its larger
 * part, until the bracket is PEAK_WIDTH wide about the best point. x, w, v (in (a, b), or x < 0: a golden
 * point is read and w, v are x) with their forces fx, fw, fv: the best point and two others known (the
 * bracket's ends). The same operations as numpy_backend.peak_search. */
static double peak_search(run *r, double t_end, double a, double b, double x, double fx, double w, double fw, double v,
                          double fv)
{
    const double golden = 0.5 * (3.0 - sqrt(5.0)), tol = 0.25 * PEAK_WIDTH;
    double d = 0.0, e = 0.0, u, fu, m, p, q, s;
    int i;
    if (x < 0.0) {
        x = w = v = a + golden * (b - a);
        fx = fw = fv = bumper_force_in_step(r, t_end, x);
    } else {
        d = e = b - a; /* the known points' parabola is tried at once */
    }
    for (i = 0; i < 100; ++i) {
        m = 0.5 * (a + b);
        if (fabs(x - m) <= 2.0 * tol - 0.5 * (b - a))
            break;
        if (fabs(e) > tol) { /* the parabola's vertex u = x + p / q through (x, -fx), (w, -fw), (v, -fv) */
            s = (x - w) * (fv - fx);
            q = (x - v) * (fw - fx);
            p = (x - v) * q - (x - w) * s;
            q = 2.0 * (q - s);
            if (q > 0.0)
                p = -p;
            q = fabs(q);
            s = e;
            e = d;
            if (fabs(p) >= fabs(0.5 * q * s) || p <= q * (a - x) || p >= q * (b - x)) {
                e = x >= m ? a - x : b - x;
                d = golden * e;
            } else {
                d = p / q;
                if ((x + d) - a < 2.0 * tol || b - (x + d) < 2.0 * tol)
                    d = m > x ? tol : -tol;
            }
        } else {
            e = x >= m ? a - x : b - x;
            d = golden * e;
        }
        u = fabs(d) >= tol ? x + d : x + (d >= 0.0 ? tol : -tol);
        fu = bumper_force_in_step(r, t_end, u);
        if (fu >= fx) {
            if (u >= x)
                a = x;
            else
                b = x;
            v = w, fv = fw, w = x, fw = fx, x = u, fx = fu;
        } else {
            if (u < x)
                a = u;
            else
                b = u;
            if (fu >= fw || w == x) {
                v = w, fv = fw, w = u, fw = fu;
            } else if (fu >= fv || v == x || v == w) {
                v = u, fv = fu;
            }
        }
    }
    return fx;
}
#endif

/* While a pad pushes, the peak of the bumpers' force over the last step up to t_end (rule 6): the dense
 * output at the step's ends and middle; where the largest of those reaches bumper_force_max, the step's
 * maximum: the largest sample, or at an end of the step the end itself where the parabola through it and
 * its two neighbours still climbs there; otherwise, where every pad is Kelvin-Voigt, at the largest point of
 * the quartic through the step's ends, quarters and middle (the force k_b delta + c_b ddelta is affine in the
 * state, the dense output a quartic in the step's fraction: the quartic is the force), else peak_search
 * between the largest sample's neighbours. The same operations as
 * numpy_backend.step_peak. bumper_at_start: the force at the step's start (the last step's end, or the
 * segment's start: the same state in every component). Returns the force at y_end. */
static double step_peak(run *r, double bumper_at_start, double t_end, const double *y_end)
{
    const int n = PEAK_POINTS - 1;
    double f[PEAK_POINTS], best;
    int i, k = 0;
    f[0] = bumper_at_start;
    for (i = 1; i < n; ++i)
        f[i] = bumper_force_in_step(r, t_end, (double)i / n);
    f[n] = bumper_force(r, y_end);
    for (i = 1; i < PEAK_POINTS; ++i)
        if (f[i] > f[k])
            k = i;
    best = f[k];
    /* At the maximum so far too: a step that starts at it (the last one's end) may climb past it. */
    if (!(best >= r->res->bumper_force_max && best > 0.0))
        return f[n];
    r->res->bumper_force_max = best;
    if (k == n && 3.0 * f[n] - 4.0 * f[n - 1] + f[n - 2] > 0.0)
        return f[n];
    if (k == 0 && -3.0 * f[0] + 4.0 * f[1] - f[2] < 0.0)
        return f[n];
#if PADS_AFFINE
    {
        double q[5], x;
        q[0] = f[0], q[2] = f[1], q[4] = f[2];
        q[1] = bumper_force_in_step(r, t_end, 0.25);
        q[3] = bumper_force_in_step(r, t_end, 0.75);
        x = quartic_peak(q);
        best = max2(best, max2(q[1], q[3]));
        if (x > 0.0 && x < 1.0)
            best = max2(best, bumper_force_in_step(r, t_end, x));
        r->res->bumper_force_max = best;
    }
#else
    if (k == 1) /* the middle, best of three: the ends bracket it and give the first parabola */
        best = peak_search(r, t_end, 0.0, 1.0, 0.5, f[1], f[0] > f[2] ? 0.0 : 1.0, max2(f[0], f[2]),
                           f[0] > f[2] ? 1.0 : 0.0, f[0] > f[2] ? f[2] : f[0]);
    else
        best = peak_search(r, t_end, k == 0 ? 0.0 : 0.5, k == 0 ? 0.5 : 1.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    r->res->bumper_force_max = max2(r->res->bumper_force_max, best);
#endif
    return f[n];
}
#endif

/* The maxima at the state y, or at the last step's end (at_step_end: the stops' contacts there are known); force:
 * the bumpers' largest force at y where known (bumper_force), else NULL. */
static ALWAYS_INLINE void see_state(run *r, const double *y, int at_step_end, const double *force)
{
    r->res->theta_max = max2(r->res->theta_max, fabs(y[0]));
#if NQ > 1
    r->res->x_max = max2(r->res->x_max, fabs(y[1]));
#endif
#if MODEL_NSTOPS > 0
    if (force != NULL)
        r->res->bumper_force_max = max2(r->res->bumper_force_max, *force);
    else if (!(at_step_end && pads_apart(&r->events)))
        r->res->bumper_force_max = max2(r->res->bumper_force_max, bumper_force(r, y));
#else
    (void)at_step_end, (void)force;
#endif
}

/* In flight, the largest |u| and corner height (u_max, jump_max) at the flying state y at t: at every step end
 * and located event point, the segment's start and end (the located peaks of the heights among them). */
static void see_flight(run *r, double t, const double *y)
{
#ifdef MODEL_FLIGHT
    r->res->u_max = max2(r->res->u_max, fabs(y[NY]));
    r->res->jump_max = max2(r->res->jump_max, max2(y[NY + 2], corner_height_other(&r->ec, t, y)));
#else
    (void)r, (void)t, (void)y;
#endif
}

/* A non-terminal event located at t inside the last step. */
static void pass_event(run *r, int kind, double t)
{
    if (r->flying) {
        double y[NA];
        memcpy(y, r->d.y, sizeof y);
        dopri_dense(&r->d, t, y);
        see_flight(r, t, y);
    }
    switch (kind) {
    case EV_CRITICAL:
        if (isnan(r->res->t_critical))
            r->res->t_critical = t;
        events_drop(&r->events, EV_CRITICAL); /* only the first crossing is wanted */
        break;
    case EV_THETA_PEAK:
        r->res->theta_max = max2(r->res->theta_max, fabs(dopri_dense1(&r->d, t, 0)));
        break;
#if NQ > 1
    case EV_X_PEAK:
        r->res->x_max = max2(r->res->x_max, fabs(dopri_dense1(&r->d, t, 1)));
        break;
#endif
#ifdef MODEL_FLIGHT
#endif
    default:
        break;
    }
}

/* The code in the table (phases.h) of the phase on the floor with these constraints: rocking, sliding. */
static int phase_of(int rocks, int slides)
{
    int i;
    for (i = 0; i < PHASE_COUNT; ++i)
        if (PHASES[i].rocks == rocks && PHASES[i].slides == slides && !PHASES[i].flies)
            return i;
    return -1; /* not reached: the table has every pair (phases.check_table) */
}

/* The code of the phase rocking about s (0: full contact) with the slip's sign sigma (0: stuck). */
static int phase_code(const run *r, int s, int sigma)
{
    return r->codes[s != 0][sigma != 0];
}

/* The code of the run's current phase (flight included). */
static int phase_current(const run *r)
{
    return r->flying ? PHASE_FLIGHT : phase_code(r, r->phase, r->sigma);
}

/* The events the phase `code` has exits on, one bit per event of the table (read once per run: the table is
 * scanned once, not at every segment). */
static unsigned phase_exit_events(int code)
{
    unsigned events = 0;
    int i;
    for (i = 0; i < PHASES[code].n_exits; ++i)
        events |= 1u << PHASES[code].exits[i].event;
    return events;
}

/* Where `event` under `guard` leads from the phase `code`: the first of its exits on that event whose guard is
 * "always" or `guard`; a phase's code, an end (< 0), or PHASE_COUNT if the table has none (not reached). */
static inline int phase_next(int code, int event, int guard)
{
    int i;
    for (i = 0; i < PHASES[code].n_exits; ++i) {
        const phase_exit *e = &PHASES[code].exits[i];
        if (e->event == event && (e->guard == PHASE_GUARD_ALWAYS || e->guard == guard))
            return e->to;
    }
    return PHASE_COUNT;
}

/* Each stop side's gap closing, or opening once its bumper acts: watched in every phase (rule 6). */
static event_mask gap_events(const run *r)
{
    event_mask active = 0;
    int k;
    for (k = 0; k < MODEL_NSTOPS; ++k)
        active |= (event_mask)1 << ((r->k->stop_on[k] ? EV_GAP_OPEN : EV_GAP_CLOSE) + k);
    (void)r;
    return active;
}

/* The events of the flight phase (its exits `exits`): the landing of either corner, overturning, and the
 * reported extrema: theta's, q[1]'s, u's, each corner's height (jump_max), and t_critical. */
static event_mask flight_events(const run *r, unsigned exits)
{
    const event_mask landing = exits >> PHASE_EVENT_LANDING & 1u;
    event_mask active = landing << EV_LANDING_S | landing << EV_LANDING_O;
    active |= (event_mask)(exits >> PHASE_EVENT_OVERTURN & 1u) << EV_FLIGHT_OVERTURN;
    active |= (event_mask)1 << EV_JUMP_S | (event_mask)1 << EV_JUMP_O;
    active |= (event_mask)1 << EV_THETA_PEAK | (event_mask)isnan(r->res->t_critical) << EV_CRITICAL;
    if (NQ > 1)
        active |= (event_mask)1 << EV_X_PEAK;
    return active | gap_events(r);
}

/* The events of docs/simulation.md for the current phase: the exits of its entry in the table (the events
 * of friction only on a floor with finite mu_s), and the reported extrema and crossings. */
static event_mask watched_events(const run *r)
{
    const unsigned exits = r->exits[phase_current(r)];
    const event_mask rest = !r->o.pulse_on && (exits >> PHASE_EVENT_REST & 1u);
    const event_mask uplift = exits >> PHASE_EVENT_UPLIFT & 1u;
    const int up = r->sigma != 0 ? EV_SLIDE_UPLIFT_A : EV_UPLIFT_A; /* the pair of either */
    event_mask active = uplift << up | uplift << (up + 1);
    if (r->flying)
        return flight_events(r, exits);
    active |= (event_mask)(exits >> PHASE_EVENT_IMPACT & 1u) << EV_IMPACT;
    active |= (event_mask)(exits >> PHASE_EVENT_OVERTURN & 1u) << EV_OVERTURN;
    active |= rest << EV_REST;
    active |= (event_mask)(rest && r->early && !r->safe) << EV_SAFE;
    if (r->phase != 0)
        active |= (event_mask)1 << EV_THETA_PEAK | (event_mask)isnan(r->res->t_critical) << EV_CRITICAL;
    if (r->friction) {
        active |= (event_mask)(exits >> PHASE_EVENT_SLIP & 1u) << EV_SLIP;
        active |= (event_mask)(exits >> PHASE_EVENT_STOP & 1u) << EV_STOP;
    }
    /* The floor's N on every floor of a model with flight; in full contact without a vertical component N is
     * the system's weight, constant (tests/test_c_flight.py checks it): not watched there. */
    if ((r->friction || FLIGHT) && (r->phase != 0 || r->o.vertical))
        active |= (event_mask)(exits >> PHASE_EVENT_LIFT_OFF & 1u) << EV_LIFT_OFF;
    /* Once safe, the next extremum of q[1] is the last one: it ends the run. */
    if (NQ > 1)
        active |= (event_mask)1 << (r->phase == 0 && r->safe ? EV_SETTLED : EV_X_PEAK);
    return active | gap_events(r);
}

/* What a segment changes in the results and the history before its end:
 * restored when the work passes max_steps inside it (rule 5). */
typedef struct segment_start {
    double theta_max, x_max, t_critical, bumper_force_max, u_max, jump_max;
    int64_t n_rec;
} segment_start;

static void segment_saved(const run *r, segment_start *saved)
{
    saved->theta_max = r->res->theta_max;
    saved->x_max = r->res->x_max;
    saved->t_critical = r->res->t_critical;
    saved->bumper_force_max = r->res->bumper_force_max;
    saved->u_max = r->res->u_max;
    saved->jump_max = r->res->jump_max;
    saved->n_rec = r->n_rec;
}

/* Rule 5: the run ends at the start of the segment in which its work passed
 * max_steps, with the results of the segments before it. (r->t, r->y) still
 * hold that start; the history drops the segment's samples. */
static int segment_undone(run *r, const segment_start *saved)
{
    r->res->theta_max = saved->theta_max;
    r->res->x_max = saved->x_max;
    r->res->t_critical = saved->t_critical;
    r->res->bumper_force_max = saved->bumper_force_max;
    r->res->u_max = saved->u_max;
    r->res->jump_max = saved->jump_max;
    if (r->hist != NULL) {
        r->n_rec = saved->n_rec; /* its last row is the segment's start */
        r->last_t = r->t;
        memcpy(r->last_y, r->y, sizeof r->last_y);
        r->last_phase = r->phase;
        r->last_sigma = r->sigma;
        r->last_flying = r->flying;
    }
    return SEG_MAX_STEPS;
}

/* The caller's stop flag is read after the first step of a segment and every STOP_POLL + 1 steps after it (a
 * few microseconds apart). */
#define STOP_POLL 15u

/* The caller's stop flag is set. */
static int stop_requested(const run *r)
{
    return r->stop != NULL && *r->stop != 0;
}

/* A flight's landings where its segment starts: a corner on the floor that rises (a bounce) is armed at once,
 * its 0 read as above the floor, so that a short hop landing within the first step is still found (one that
 * does not rise, a takeoff, is armed once its height is positive: the events' strict rule). */
static void flight_landings_armed(run *r)
{
#ifdef MODEL_FLIGHT
    int k;
    for (k = 0; k < r->events.n; ++k) {
        const int kind = r->events.w[k].kind;
        if (!(r->events.g[k] == 0.0 && (kind == EV_LANDING_S || kind == EV_LANDING_O)))
            continue;
        if ((kind == EV_LANDING_S ? r->y[NY + 3] : corner_rate_other(&r->ec, r->t, r->y)) > 0.0)
            r->events.g[k] = DBL_MIN;
    }
#else
    (void)r;
#endif
}

/* Integrate the current phase from (r->t, r->y) until t_bound or a terminal
 * event; (r->t, r->y) is then the segment's end. Returns the event, or
 * SEG_BOUND, SEG_FAILED, SEG_NO_LIFT, SEG_NO_SLIP, SEG_MAX_STEPS (then (r->t, r->y) is
 * still the segment's start), SEG_STOPPED. */
static int run_segment(run *r, double t_bound)
{
    const double s = (double)r->phase;
    /* While the pulse acts, the bare block's contact phase has no dynamics at
     * all: only a bounded step keeps an uplift from being stepped over. */
    const double max_step = (r->phase == 0 && r->t < r->c->t_p) ? r->c->contact_max_step : INFINITY;
    /* Rocking from theta = 0 (an uplift, an impact): s theta must turn
     * positive, or the impact event (armed by s theta > 0) would never fire. */
    int lifting = !r->flying && r->phase != 0 && r->y[0] == 0.0;
    /* Sliding from du = 0 (a slip starts, reverses): sigma du must turn positive, or the stop event would
     * never fire, and friction would push the base along. */
    int slipping = r->sigma != 0 && r->y[NS - 1] == 0.0;
    /* Taking off from v = dv = 0: v must turn positive, or the landing event (armed by v > 0) would never fire
     * and the corner would sink through the floor; so must the other corner's height where it starts at 0 too
     * (a flat base). (A bounce, dv > 0, has its landing armed at once: flight_landings_armed.) */
    int launching = r->flying && corner_height(r->y) == 0.0 && !corner_rising(r->y);
    int corner_flat = 0;
    int starting = lifting || slipping || launching;
    /* A sampled motion while it acts: every step ends at the next sample time at
     * the latest (a kink of ag), inside the segment. ag is continuous there, so
     * the step's last stage is still the next one's first (FSAL). */
    const int sampled = r->c->motion == ROCKING_MOTION_SAMPLED && r->t < r->c->t_p;
    unsigned polls = 0;
    dopri_step_fn dopri_step;
    step_events found;
    segment_start saved;
    event_mask active;
    int k;
#if MODEL_NSTOPS > 0
    double force = 0.0; /* the bumpers' largest force at the last step's end (the segment's start first) */
    int pushing = 0; /* a pad pushes in this segment (its regime is constant) */
    for (k = 0; k < MODEL_NSTOPS; ++k)
        pushing |= r->k->stop_on[k];
#endif

    segment_saved(r, &saved);
    r->o.phase = r->phase;
    if (r->friction || FLIGHT) { /* else the contact sticks throughout: as simulate_one set them */
        r->o.sigma = r->sigma;
        r->o.flying = r->flying;
        r->o.ny = r->flying ? NA : r->sigma != 0 ? NS : NY;
        r->o.mu_slip = r->friction ? r->c->mu_k * r->sigma : 0.0;
        if (r->friction || MODEL_NSTOPS > 0)
            regime_inputs(r->k, r->o.on);
    }
    r->o.cst = about(r->k, (double)r->phase);
    r->o.pulse_on = r->t < r->c->t_p;
    if (!r->o.pulse_on) /* a last a_g f(t) of the pulse is none once it has ended */
        r->o.memo_t = NAN;
    r->o.vertical = r->o.pulse_on && r->c->a_v != 0.0;
    r->o.rhs = ode_rhs_kind(&r->o);
    r->ec.bound_live = r->ec.bound.ready && (r->o.rhs == ODE_FREE_ROCKING || r->o.rhs == ODE_PULSE_ROCKING);
    r->ec.bound_side = r->phase < 0;
    r->ec.bound_rho = r->ec.bound.rho[r->ec.bound_side];
    if (sampled)
        r->o.piece = pulse_piece(r->c, r->t);
    if (!r->flying && r->phase != 0 && r->y[0] == 0.0) /* a half-cycle starts (not a restart at t_p) */
        r->t_start = r->t;
    dopri_start(&r->d, &r->o, &r->tol, r->t, r->y, t_bound, r->h_first);
    dopri_step = dopri_stepper(&r->d, &r->o);
    corner_flat = launching && corner_other_height(&r->ec, r->t, r->y) == 0.0;
    r->h_first = 0.0;
    if (over_budget(r))
        return segment_undone(r, &saved);
    active = watched_events(r);
    events_start(&r->events, &r->ec, active, r->t, r->y, r->d.f);
#if MODEL_NSTOPS > 0
    /* After a jump of the velocities the start is a state no step end has shown (rule 6); where no pad pushes and
     * every contact there is <= 0 (read by events_start), every bumper force is 0 (pads_apart). */
    if (pushing || !pads_apart(&r->events)) {
        force = bumper_force(r, r->y);
        r->res->bumper_force_max = max2(r->res->bumper_force_max, force);
    }
#endif
    /* N <= 0 where the phase starts (after an impact, a landing, at t = 0): the block takes off at once (the
     * event sees only a sign change inside a step). */
    if (active >> EV_LIFT_OFF & 1u && !r->skip_lift_check && r->events.g[event_index(active, EV_LIFT_OFF)] < 0.0)
        return EV_LIFT_OFF;
    r->skip_lift_check = 0;
    /* The flight's start counts towards u_max and jump_max as its other points do (numpy_backend's _peaks): a
     * takeoff while the raised corner falls (with a damper) has its highest point there. A takeoff's start counts
     * once its first step has lifted the corner: a grazing one (SEG_NO_TAKEOFF) is no flight. */
    if (r->flying) {
        flight_landings_armed(r);
        if (!launching)
            see_flight(r, r->t, r->y);
    }
    if (r->hist != NULL && r->c->record_dt > 0.0)
        r->next_sample = record_first_sample(r->t, r->c->record_dt);

    while (r->d.t < t_bound) {
        double step_bound = t_bound;
        if (sampled) {
            r->o.piece = pulse_piece(r->c, r->d.t);
            step_bound = fmin(t_bound, (r->o.piece + 1.0) * r->c->pulse_dt);
        }
        if (dopri_step(&r->d, &r->o, &r->tol, step_bound, max_step) != 0)
            return over_budget(r) ? segment_undone(r, &saved) : SEG_FAILED;
        if (over_budget(r))
            return segment_undone(r, &saved);
        if ((polls++ & STOP_POLL) == 0 && stop_requested(r))
            return SEG_STOPPED;
        if (starting) {
            const int lifted = !lifting || s * r->d.y[0] > 0.0;
            const int bounced =
                !launching || (corner_height(r->d.y) > 0.0 && !(corner_flat && !(corner_other_height(&r->ec, r->d.t, r->d.y) > 0.0)));
            if (!(lifted && bounced && (!slipping || r->sigma * r->d.y[NS - 1] > 0.0))) {
                /* The block fell back within the first step (or never rose), or the base did not move
                 * in the slip's direction, or the corner fell back to the floor: retry shorter; if even the
                 * shortest step cannot lift it (slip it, bounce it), it does not lift (slip, bounce): a
                 * grazing uplift (slip, bounce). */
                const double h = 0.1 * r->d.h;
                if (h < min_step_at(r->d.t_old))
                    return !bounced ? SEG_NO_TAKEOFF : lifted ? SEG_NO_SLIP : SEG_NO_LIFT;
                dopri_undo(&r->d, h);
                continue;
            }
            starting = 0;
            if (launching) /* the takeoff's state, now that the block flies (see above) */
                see_flight(r, r->t, r->y);
        }
        events_scan(&r->events, &r->ec, &r->d, &found);
        for (k = 0; k < found.n_passed; ++k)
            pass_event(r, found.passed[k], found.t_root[found.passed[k]]);
        if (r->hist != NULL) {
            record_samples(r, found.t_stop);
            if (over_budget(r)) /* the samples count (the step was checked above) */
                return segment_undone(r, &saved);
        }
        if (found.terminal >= 0) {
            r->t = found.t_stop;
            dopri_dense(&r->d, r->t, r->y);
#if MODEL_NSTOPS > 0
            if (pushing)
                force = step_peak(r, force, r->t, r->y);
            see_state(r, r->y, 0, pushing ? &force : NULL);
#else
            see_state(r, r->y, 0, NULL);
#endif
            if (r->flying)
                see_flight(r, r->t, r->y);
            if (found.terminal == EV_IMPACT)
                r->y[0] = 0.0; /* the impact is at theta = 0; the root is 0 only to the tolerance */
            if (found.terminal == EV_STOP)
                r->y[NS - 1] = 0.0; /* the slip stops at du = 0 */
            return found.terminal;
        }
#if MODEL_NSTOPS > 0
        if (pushing)
            force = step_peak(r, force, r->d.t, r->d.y);
        see_state(r, r->d.y, 1, pushing ? &force : NULL);
#else
        see_state(r, r->d.y, 1, NULL);
#endif
        if (r->flying)
            see_flight(r, r->d.t, r->d.y);
    }
    r->t = t_bound;
    memcpy(r->y, r->d.y, sizeof r->y);
    return SEG_BOUND;
}

#ifdef MODEL_FRICTION
/* uplift_at_start where the base slides: its uplift functions written with the friction force. */
static int slide_uplift_at_start(const run *r)
{
    ode o;
    event_ctx ec = r->ec;
    ode_at(r, r->t, &o);
    ec.o = &o;
    if (slide_uplift_event(&ec, 1.0, r->t, r->y) > 0.0)
        return 1;
    if (slide_uplift_event(&ec, -1.0, r->t, r->y) > 0.0)
        return -1;
    return 0;
}
#endif

/* Pivot whose uplift function is already positive when full contact starts, else 0. */
static int uplift_at_start(const run *r)
{
#ifdef MODEL_FRICTION
    if (r->sigma != 0)
        return slide_uplift_at_start(r);
#endif
    const double ag = r->t < r->c->t_p ? pulse_at(r->c, r->t) : 0.0;
    const double agy = r->t < r->c->t_p ? vertical_at(r->c, r->t) : 0.0;
    double at_gravity[2][NK];
    const double *a = about(r->o.k, 1.0), *b = about(r->o.k, -1.0);
    if (agy != 0.0) {
        constants_at_gravity(r->o.k, 1.0, agy, at_gravity[0]);
        constants_at_gravity(r->o.k, -1.0, agy, at_gravity[1]);
        a = at_gravity[0], b = at_gravity[1];
    }
    if (model_uplift_prepared(r->y, ag, a) > 0.0)
        return 1;
    if (model_uplift_prepared(r->y, ag, b) > 0.0)
        return -1;
    return 0;
}

#ifdef MODEL_FRICTION
/* The kinetic energy the slip speed adds to the energy (0 where the contact sticks). */
static double slip_energy(const run *r)
{
    if (r->y[NY + 1] != 0.0) {
        double on[2 * MAX_STOP_SIDES];
        regime_inputs(r->k, on);
        return model_slip_energy(r->phase < 0 ? -1.0 : 1.0, r->y, 0.0, 0.0, r->k->p, MODEL_NSTOPS > 0 ? on : NULL,
                                 r->y[NY + 1]);
    }
    return 0.0;
}
#endif

/* The energy above rest, the slip's included. */
static inline double energy_above_rest(const run *r)
{
    const double energy = model_energy_prepared(r->y, 0.0, about(r->o.k, r->phase < 0 ? -1.0 : 1.0)) - r->ec.energy_zero;
#ifdef MODEL_FRICTION
    if (r->y[NY + 1] != 0.0)
        return energy + slip_energy(r);
#endif
    return energy;
}

/* Settling ends before it starts: nothing to settle without attached bodies,
 * and dq[1] = 0 is the extremum itself. */
static int settled_at_once(const run *r)
{
#if NQ > 1
    return r->y[NQ + 1] == 0.0;
#else
    (void)r;
    return 1;
#endif
}

/* The least energy above rest at which the attached bodies can lift the block,
 * with the safety margin of rule 4; NaN when no bound applies (a bound of 0
 * about either pivot, or NaN). */
static double safe_energy(const constants *k, double reach)
{
    const double zeros[NY] = {0.0};
    const double a = model_uplift_energy_prepared(zeros, 0.0, about(k, 1.0));
    const double b = model_uplift_energy_prepared(zeros, 0.0, about(k, -1.0));
#if MODEL_NSTOPS > 0
    /* With stops, also out of every pad's reach (pad_reach). */
    if (!(a > 0.0 && b > 0.0 && reach > 0.0))
        return NAN;
    return min2(min2(a, b) * (1.0 - ROCKING_SAFE_MARGIN), reach);
#else
    (void)reach;
    if (!(a > 0.0 && b > 0.0))
        return NAN;
    return min2(a, b) * (1.0 - ROCKING_SAFE_MARGIN);
#endif
}

/* The lesser of two values, NaN if either is. */
static double lower(double a, double b)
{
    return (a < b || isnan(a)) ? a : b;
}

/* The least potential at |theta| = theta_m about either pivot (generated
 * least_potential; the bumpers' energy left out, a lower bound). */
static double least_at_tilt(const run *r, double theta_m)
{
    double y[NY] = {0.0};
    double a, b;
    y[0] = theta_m;
    a = model_least_potential_prepared(y, 0.0, about(r->k, 1.0));
    y[0] = -theta_m;
    b = model_least_potential_prepared(y, 0.0, about(r->k, -1.0));
    return lower(a, b);
}

#if NQ > 1

static void arcs_prepare(const run *r, double theta_m, arcs *a)
{
    double p[MODEL_NP];
    a->n = theta_m > 0.0 ? (int)ceil(theta_m / ROCKING_ARC_STEP) : 1;
    a->w = theta_m / a->n;
    memcpy(p, r->k->p, sizeof p);
    p[MODEL_P_GRAVITY] /= cos(0.5 * a->w);
    constants_prepare(&a->outer, p, r->k->stop_on);
}

/* The least potential with |q[1]| = x_m over the tilts |theta| <= theta_m
 * about either pivot (rule 4). The potential is linear in (cos, sin) of the
 * tilt with the attached positions held, so its least over them (generated
 * least_stroke_potential) is concave in that point: on an arc [a, b] of
 * width w <= ARC_STEP, the least is at a corner of the triangle that holds
 * the arc: its ends, and the ends' tangents' meeting point (cos, sin) of
 * (a + b) / 2 times 1 / cos(w / 2). The weights' potential is proportional to
 * g: that point is the middle tilt under gravity g / cos(w / 2). */
static double least_on_arcs(const run *r, const arcs *a, double x_m)
{
    double y[NY] = {0.0}, least = INFINITY;
    int i, side, pivot;
    for (pivot = 0; pivot < 2; ++pivot) {
        const double s = pivot ? -1.0 : 1.0;
        for (side = 0; side < 2; ++side) {
            y[1] = side ? -x_m : x_m;
            for (i = 0; i <= a->n; ++i) {
                y[0] = s * a->w * i;
                least = lower(least, model_least_stroke_potential_prepared(y, 0.0, about(r->k, s)));
            }
            for (i = 0; i < a->n; ++i) {
                y[0] = s * a->w * (i + 0.5);
                least = lower(least, model_least_stroke_potential_prepared(y, 0.0, about(&a->outer, s)));
            }
        }
    }
    return least;
}
#endif

#if NQ > 1
/* No bumper can act while |q[1]| <= x_m: every gap (affine in q[1] alone,
 * derive checks it) is <= 0 at both ends. */
static int stops_out_of_reach(const run *r, double x_m)
{
#if MODEL_NSTOPS > 0
    double y[NY] = {0.0}, gaps[MODEL_NSTOPS];
    int i, side;
    for (side = 0; side < 2; ++side) {
        y[1] = side ? -x_m : x_m;
        model_stop_gaps_prepared(y, 0.0, about(r->k, 1.0), gaps);
        for (i = 0; i < MODEL_NSTOPS; ++i)
            if (!(gaps[i] <= 0.0))
                return 0;
    }
#else
    (void)r;
    (void)x_m;
#endif
    return 1;
}

/* The least potential where a stop side's gap closes, over the tilts of the arcs a: a mass
 * inside every gap with less energy can never reach a bumper. Each gap is affine in q[1] alone
 * (derive checks it): its root from its values at q[1] = 0 and 1. */
static double least_at_bumpers(const run *r, const arcs *a)
{
    double least = INFINITY;
#if MODEL_NSTOPS > 0
    double y[NY] = {0.0}, at0[MODEL_NSTOPS], at1[MODEL_NSTOPS];
    int i;
    model_stop_gaps_prepared(y, 0.0, about(r->k, 1.0), at0);
    y[1] = 1.0;
    model_stop_gaps_prepared(y, 0.0, about(r->k, 1.0), at1);
    for (i = 0; i < MODEL_NSTOPS; ++i)
        least = lower(least, least_on_arcs(r, a, fabs(at0[i] / (at0[i] - at1[i]))));
#else
    (void)r;
    (void)a;
#endif
    return least;
}
#endif

/* least_at_tilt of theta_m, evaluated again only when theta_max grows. */
static double least_at_tilt_kept(run *r, double theta_m)
{
    if (!(theta_m == r->least_tilt_at)) {
        r->least_tilt_at = theta_m;
        r->least_tilt = least_at_tilt(r, theta_m);
    }
    return r->least_tilt;
}

/* The bound of the energy above rest for the least potential `least` (rule 4's margin). */
static double below_least(double least, double zero)
{
    return least - zero - ROCKING_SAFE_MARGIN * (fabs(least) + fabs(zero));
}

#if NQ > 1 && MODEL_NSTOPS > 0
/* The energy above rest below which the mass of the upright block, inside every gap, can never reach a
 * pad: the least potential where a gap closes at theta = 0, less E(0) and the margin (NaN: no bound). */
static double pad_reach(const run *r)
{
    arcs upright;
    arcs_prepare(r, 0.0, &upright);
    return below_least(least_at_bumpers(r, &upright), r->ec.energy_zero);
}
#endif

/* energy_above_rest with the elastic energy of every pad the mass is in, pushing or released: a released
 * pad may push again (rule 4). */
static double loaded_energy_above_rest(const run *r)
{
#if MODEL_NSTOPS > 0
    constants loaded = *r->k;
    int stop_on[MAX_STOP_SIDES] = {0}, i, other = 0;
    for (i = 0; i < MODEL_NSTOPS; ++i) {
        stop_on[i] = stop_gap(r->k, r->y, i) > 0.0;
        other |= stop_on[i] != r->k->stop_on[i];
    }
    if (other) {
        constants_prepare(&loaded, r->k->p, stop_on);
#ifdef MODEL_FRICTION
        if (r->y[NY + 1] != 0.0)
            return model_energy_prepared(r->y, 0.0, about(&loaded, r->phase < 0 ? -1.0 : 1.0)) - r->ec.energy_zero +
                   slip_energy(r);
#endif
        return model_energy_prepared(r->y, 0.0, about(&loaded, r->phase < 0 ? -1.0 : 1.0)) - r->ec.energy_zero;
    }
#endif
    return energy_above_rest(r);
}

/* t_max reached: after the pulse, an energy below the least potential at some tilt |theta| < pi/2 about either
 * pivot (least_at_tilt) can never carry the block past that tilt, which every run that overturns passes: the
 * run is safe, its maxima those until t_max (rule 4); otherwise it has no verdict. Models whose energy may grow
 * get -inf from least_potential, hence no bound. */
static int safe_at_t_max(const run *r)
{
    double least = -INFINITY;
    int i;
    if (!(r->t >= r->c->t_p))
        return ROCKING_T_MAX;
    for (i = 1; i < ROCKING_BARRIER_TILTS; ++i) {
        const double at = least_at_tilt(r, HALF_PI * i / ROCKING_BARRIER_TILTS);
        if (at > least) /* a NaN is no bound */
            least = at;
    }
    return loaded_energy_above_rest(r) < below_least(least, r->ec.energy_zero) ? ROCKING_BELOW_BARRIER : ROCKING_T_MAX;
}

/* The energy above rest below which |theta| can no longer reach theta_max,
 * |q[1]| x_max, nor, where x_max is past a bumper's gap, the mass that gap
 * (rule 4): the least potential there less E(0), less the margin; -inf when
 * none applies. Kept until a maximum grows. */
static double verdict_bound(run *r)
{
    const double theta_m = r->res->theta_max, x_m = r->res->x_max;
    double least;
    if (theta_m == r->bound_at[0] && x_m == r->bound_at[1])
        return r->bound;
    r->bound_at[0] = theta_m;
    r->bound_at[1] = x_m;
    least = least_at_tilt_kept(r, theta_m);
#if NQ > 1
    if (!(theta_m == r->arcs_at)) {
        r->arcs_at = theta_m;
        arcs_prepare(r, theta_m, &r->tilts);
    }
    least = lower(least, least_on_arcs(r, &r->tilts, x_m));
    if (!stops_out_of_reach(r, x_m))
        least = lower(least, least_at_bumpers(r, &r->tilts));
#endif
    r->bound = below_least(least, r->ec.energy_zero);
    if (isnan(r->bound))
        r->bound = -INFINITY;
    return r->bound;
}

/* energy is at least verdict_bound, found from a few of the potentials whose least the bound
 * takes: at |theta| = theta_max, and at the stroke x_max upright (the first corners of
 * least_on_arcs). Their least is >= the bound's; below_least is increasing but for its rounding,
 * a few ulps of |least| + |E(0)|, which the 8 eps of that sum cover. Most impacts after the
 * pulse are not final: they need not take the bound over every arc. */
static int verdict_refuted(run *r, double energy)
{
    const double zero = r->ec.energy_zero;
    double least;
    least = least_at_tilt_kept(r, r->res->theta_max);
#if NQ > 1
    if (!(r->res->x_max == r->least_stroke_at)) { /* after the pulse x_max seldom grows: kept */
        double y[NY] = {0.0};
        r->least_stroke_at = r->res->x_max;
        y[1] = r->res->x_max;
        r->least_stroke = model_least_stroke_potential_prepared(y, 0.0, about(r->k, 1.0));
        y[1] = -r->res->x_max;
        r->least_stroke = lower(r->least_stroke, model_least_stroke_potential_prepared(y, 0.0, about(r->k, 1.0)));
    }
    least = lower(least, r->least_stroke); /* lower propagates a NaN: the same least in either order */
#endif
    return energy >= below_least(least, zero) + 8.0 * DBL_EPSILON * (fabs(least) + fabs(zero));
}

/* No bumper acts now: the mass is inside every gap (a released pad may push again). */
static int stops_clear(const run *r)
{
    int i;
    for (i = 0; i < MODEL_NSTOPS; ++i)
        if (r->k->stop_on[i] || stop_gap(r->k, r->y, i) > 0.0)
            return 0;
    return 1;
}

#if MODEL_NSTOPS > 0
/* Each stop side's regime read again from the state (rule 6), after a jump of the velocities and
 * where a segment starts: never carried over. A side that starts pushing there is a contact. */
static void stops_read(run *r)
{
    double contacts[MAX_STOP_SIDES];
    int stop_on[MAX_STOP_SIDES], i, changed = 0;
    stop_contacts_at(r->k, r->y, contacts);
    memcpy(stop_on, r->k->stop_on, sizeof stop_on);
    for (i = 0; i < MODEL_NSTOPS; ++i) {
        const int on = contacts[i] > 0.0;
        r->res->stop_contacts += on && !stop_on[i];
        changed |= on != stop_on[i];
        stop_on[i] = on;
    }
    if (changed)
        constants_switch(r->k, &r->regimes, stop_on);
}
#endif

/* After the pulse, the energy can no longer carry |theta| or |q[1]| to their
 * maxima: the verdict, the maxima and t_critical are final (rule 4). */
static int verdict_final(run *r)
{
    double energy;
    if (!(r->verdict && r->t >= r->c->t_p && stops_clear(r)))
        return 0;
    energy = energy_above_rest(r);
    return !(SHORTCUTS && verdict_refuted(r, energy)) && energy < verdict_bound(r);
}

static int events_exhausted(const run *r)
{
    return r->res->uplifts + r->res->impacts + r->res->flights >= r->c->max_events;
}

/* The rest snap after an impact (rule 2): dtheta = 0, and each other
 * velocity keeps what its impact law keeps. A coordinate j with the velocity
 * law keeps dq[j]; those with the momentum law keep their generalised momenta
 * (M dq)_j, M the mass matrix about the new pivot (constants cst): with
 * dtheta' = 0 and the velocity-law coordinates unchanged, the momentum-law
 * block m of the velocities moves by delta, M_mm delta = M_m0 dtheta. Gauss
 * elimination without pivoting (M_mm is symmetric positive definite), the
 * same operations as numpy_backend.rest_snap. */
static void rest_snap(run *r, const double *cst)
{
#if NQ > 1
    double mm[NQ * NQ], a[NQ][NQ], b[NQ], delta[NQ];
    int idx[NQ], n = 0, i, j, k;
    const double dtheta = r->y[NQ];
    model_mass_matrix_prepared(r->y, 0.0, cst, mm);
    for (i = 1; i < NQ; ++i)
        if (r->velocity_law == NULL || !r->velocity_law[i])
            idx[n++] = i;
    for (i = 0; i < n; ++i) {
        for (j = 0; j < n; ++j)
            a[i][j] = mm[idx[i] * NQ + idx[j]];
        b[i] = mm[idx[i] * NQ] * dtheta;
    }
    for (k = 0; k < n; ++k)
        for (i = k + 1; i < n; ++i) {
            const double f = a[i][k] / a[k][k];
            for (j = k; j < n; ++j)
                a[i][j] -= f * a[k][j];
            b[i] -= f * b[k];
        }
    for (i = n - 1; i >= 0; --i) {
        double sum = b[i];
        for (j = i + 1; j < n; ++j)
            sum -= a[i][j] * delta[j];
        delta[i] = sum / a[i][i];
    }
    for (i = 0; i < n; ++i)
        r->y[NQ + idx[i]] += delta[i];
#else
    (void)cst;
#endif
    r->y[NQ] = 0.0;
}

/* Into the phase `to` of the table after an event, or its end (to < 0: the status): about the pivot s where
 * it rocks, the slip's sign sigma where it slides (else the contact sticks, du = 0). A stuck contact that
 * starts sliding is a slip episode (slip_stops counts a reversal). Returns 1 where the run ends, else 0. */
static int enter(run *r, int to, int s, int sigma)
{
    /* A model without flight functions does not follow flight: the base leaves the floor, out of its scope
     * (section 14). */
    if (to < 0 || to >= PHASE_COUNT || (!FLIGHT && PHASES[to].flies)) {
        r->res->status = to == PHASE_END_OVERTURNED ? ROCKING_OVERTURNED
                         : to == PHASE_END_REST     ? ROCKING_REST
                         : to == PHASE_END_JAMMED   ? ROCKING_JAMMED
                         : to >= 0                  ? ROCKING_FLIGHT
                                                    : ROCKING_FAILED; /* not reached: the table has the exit */
        return 1;
    }
    /* A slip episode: a stuck contact starts sliding (not a landing that slides on: numpy_backend's count). */
    r->res->slides += PHASES[to].slides && !PHASES[to].flies && r->sigma == 0 && !r->flying;
    r->phase = PHASES[to].rocks ? s : 0;
    /* A stuck phase is entered with du = 0: a stop, a holding impact; in flight the contact neither sticks
     * nor slides (sigma 0), u and du are integrated. */
    r->sigma = PHASES[to].slides && !PHASES[to].flies ? sigma : 0;
    r->flying = PHASES[to].flies;
    return 0;
}

#ifdef MODEL_FLIGHT
/* The floor's normal force on the contact is < 0 at the run's state: the block takes off at once. */
static int lift_off_at_start(const run *r)
{
    double fn[2];
    floor_force_at(r, r->t, r->y, fn);
    return fn[1] < 0.0;
}
#endif

#ifdef MODEL_FLIGHT
/* At a takeoff of a stuck corner of a floor without friction: 1 where the free flight does not lift the corner.
 * The margin's zero where -ddv reaches 0 leaves ddv = 0 up to rounding, and whether the flight rises is then the
 * sign of its own rate of change: ddv is read TAKEOFF_PROBE along the flight (one Euler step of the rocking state)
 * at either zero of the margin alike, as numpy_backend's corner_sinks does (docs/simulation.md, "Flight"). */
static int corner_sinks(run *r)
{
    double out[NQ + 2], probe[NY];
    const double t = r->t + ROCKING_TAKEOFF_PROBE;
    int j;
    if (r->friction || r->phase == 0 || r->sigma != 0)
        return 0;
    model_flight_accel((double)r->phase, r->y, ode_ag(&r->o, r->t), ode_agy(&r->o, r->t), r->k->p, friction_on(&r->o),
                       out);
    for (j = 0; j < NQ; ++j) {
        probe[j] = r->y[j] + ROCKING_TAKEOFF_PROBE * r->y[NQ + j];
        probe[NQ + j] = r->y[NQ + j] + ROCKING_TAKEOFF_PROBE * out[j];
    }
    model_flight_accel((double)r->phase, probe, ode_ag(&r->o, t), ode_agy(&r->o, t), r->k->p, friction_on(&r->o), out);
    return !(out[NQ + 1] > 0.0);
}

/* A grazing takeoff (its corner cannot rise): the block stays in the phase it took off from, no flight; its
 * N <= 0 there is not checked again until it is positive (skip_lift_check). */
static void lift_off_grazing(run *r)
{
    r->res->flights -= 1;
    r->flying = 0;
    r->phase = r->lift_phase;
    r->sigma = r->lift_sigma;
    r->y[NY + 3] = 0.0;
    r->skip_lift_check = 1;
}
#endif

#ifdef MODEL_FRICTION
/* The lift-off event: the block leaves the floor about the reference corner s, the pivot when rocking, +1 from
 * full contact; u and du as they are, v = dv = 0 (docs/model.md section 16). Where the table leads (a model
 * without flight ends the run there); returns 1 where the run ends. A grazing takeoff stays on the floor, and
 * the next segment starts with step, the size of the step in which the event fired (0 at a phase's start:
 * Hairer's heuristic), as numpy_backend's takeoff does. */
static int takeoff(run *r, double step)
{
    const int s = r->phase != 0 ? r->phase : 1, phase = r->phase, sigma = r->sigma;
#ifdef MODEL_FLIGHT
    if (corner_sinks(r)) {
        r->skip_lift_check = 1; /* no flight: the pivot is held, its lift-off armed by a sign change again */
        r->h_first = step;
        return 0;
    }
#endif
    if (enter(r, phase_next(phase_current(r), PHASE_EVENT_LIFT_OFF, PHASE_GUARD_ALWAYS), s, 0))
        return 1;
#ifdef MODEL_FLIGHT
    r->y[NY + 2] = r->y[NY + 3] = 0.0;
    r->res->flights += 1;
    r->lift_phase = phase;
    r->lift_sigma = sigma;
    r->t_takeoff = r->t;
    r->safe = 0;
#endif
    return 0;
}

/* takeoff, then the run's end where the takeoff ends it or exhausts max_events (its flight counts); returns 1
 * where the run ends. */
static int lift_off_counted(run *r, double step)
{
    if (takeoff(r, step))
        return 1;
    if (events_exhausted(r)) {
        r->res->status = ROCKING_MAX_EVENTS;
        return 1;
    }
    return 0;
}
#endif

#ifdef MODEL_FRICTION
/* The impact with friction (docs/model.md section 15) about s: the velocities after it into dq and du
 * (r->y[NY + 1]); the corner holds (returns 0) if the impulse that stops it is within mu_s P_n, else it slides
 * through the impact against that impulse (returns the sign of du after it). */
static int impact_friction(run *r, double s, double *dq)
{
    double on[2 * MAX_STOP_SIDES], stick[NQ + 3], slide[NQ + 3];
    const double du = r->y[NY + 1];
    const double *inputs = MODEL_NSTOPS > 0 ? on : NULL;
    regime_inputs(r->k, on);
    model_impact_stick(s, r->y, 0.0, 0.0, r->k->p, inputs, du, stick);
    if (fabs(stick[NQ + 1]) <= r->c->mu_s * stick[NQ + 2]) {
        /* From a stuck pivot the map is (I1)-(I2): the prepared one gives the bits of a floor that never slips. */
        if (du == 0.0)
            model_impact_prepared(r->y, ode_ag(&r->o, r->t), about(r->o.k, s), dq);
        else
            memcpy(dq, stick, NQ * sizeof *dq);
        r->y[NY + 1] = 0.0;
        return 0;
    }
    model_impact_slide(s, r->y, 0.0, 0.0, r->k->p, inputs, du, r->c->mu_k * (stick[NQ + 1] > 0.0 ? -1.0 : 1.0),
                       slide);
    memcpy(dq, slide, NQ * sizeof *dq);
    r->y[NY + 1] = slide[NQ];
    return (slide[NQ] > 0.0) - (slide[NQ] < 0.0);
}
#endif

/* The impact that ends rocking about s: theta = 0 already, dq = J_s(y); the
 * block rests if the outgoing |dtheta| is below dtheta_rest. Where the table
 * leads (enter); returns 1 where the run ends. */
static int impact(run *r)
{
    double dq[NQ];
    const double s = (double)r->phase;
    const double dtheta_in = r->y[NQ];
    const int code = phase_code(r, r->phase, r->sigma);
    int sigma = 0, rests, ended;
#if MODEL_NSTOPS > 0
    double before[NA];
    memcpy(before, r->y, sizeof before);
#endif
#ifdef MODEL_FRICTION
    if (r->friction)
        sigma = impact_friction(r, s, dq);
    else
#endif
        model_impact_prepared(r->y, ode_ag(&r->o, r->t), about(r->o.k, s), dq);
    memcpy(r->y + NQ, dq, sizeof dq);
    r->res->impacts += 1;
    rests = fabs(r->y[NQ]) < r->c->dtheta_rest;
    if (rests) {
        rest_snap(r, about(r->o.k, -s)); /* the new pivot's mass matrix */
    } else {
        /* The corner that just hit the ground is the new pivot. The next
         * half-cycle lasts about this one times |dtheta+ / dtheta-|: its first
         * step is a fraction of that (docs/simulation.md, Integration). */
        const double h = ROCKING_FIRST_STEP_FRACTION * (r->t - r->t_start) * fabs(r->y[NQ] / dtheta_in);
        r->h_first = isfinite(h) ? h : 0.0;
    }
    ended = enter(r,
                  phase_next(code, PHASE_EVENT_IMPACT,
                             sigma != 0 ? (rests ? PHASE_GUARD_RESTS_SLIDING : PHASE_GUARD_ROCKS_SLIDING)
                                        : (rests ? PHASE_GUARD_RESTS : PHASE_GUARD_ROCKS)),
                  -r->phase, sigma);
#if MODEL_NSTOPS > 0
    /* The velocities jumped: the pads' memory and regime follow the state (rule 6). */
    stop_memory_jump(r->k, before, r->y);
    stops_read(r);
#endif
    return ended;
}

#ifdef MODEL_FRICTION
/* The floor's force on a contact where a segment starts: the run ends in flight where N <= 0 (lift-off); a
 * stuck contact the floor cannot hold, |F| >= mu_s N, slips at once against F (unless check_slip is 0: a slip
 * that could not start there). Returns 1 where the run ends, else 0. */
static int floor_at_start(run *r, int check_slip)
{
    double fn[2];
    const int code = phase_code(r, r->phase, r->sigma);
    floor_force_at(r, r->t, r->y, fn);
    if (fn[1] <= 0.0 && !r->skip_lift_check)
        return takeoff(r, 0.0);
    /* At the floor's limit too: a phase that starts there (an uplift where ag crosses mu_s g as the uplift
     * threshold, mu_s = tan alpha) holds its contact only to rounding (the slip event needs it to fall from > 0). */
    if (check_slip && r->sigma == 0 && r->c->mu_s * fn[1] - fabs(fn[0]) <= 0.0)
        return enter(r, phase_next(code, PHASE_EVENT_SLIP, PHASE_GUARD_ALWAYS), r->phase, fn[0] > 0.0 ? -1 : 1);
    return 0;
}

/* Where a slip ends (du = 0): the stuck phase's force decides; the contact holds if |F| <= mu_s N, else the
 * slip reverses, against F: it stopped for an instant, the slip the other way is a new episode. Returns 1
 * where the run ends. */
static int slip_stops(run *r)
{
    double fn[2];
    const int code = phase_code(r, r->phase, r->sigma), sigma = r->sigma;
    r->sigma = 0;
    floor_force_at(r, r->t, r->y, fn);
    r->sigma = sigma;
    r->res->slides += fabs(fn[0]) > r->c->mu_s * fn[1];
    return enter(r,
                 phase_next(code, PHASE_EVENT_STOP,
                            fabs(fn[0]) <= r->c->mu_s * fn[1] ? PHASE_GUARD_HOLDS : PHASE_GUARD_SLIPS),
                 r->phase, fn[0] > 0.0 ? -1 : 1);
}

/* Where the slip event fires: the stuck contact starts sliding against F. Returns 1 where the run ends. */
static int slip_starts(run *r)
{
    double fn[2];
    floor_force_at(r, r->t, r->y, fn);
    return enter(r, phase_next(phase_code(r, r->phase, r->sigma), PHASE_EVENT_SLIP, PHASE_GUARD_ALWAYS), r->phase,
                 fn[0] > 0.0 ? -1 : 1);
}
#endif

#ifdef MODEL_FLIGHT
/* How a landing's impulse is consistent (docs/model.md section 16; rocking/reference/flight.py landing_law). */
enum { LAW_JAM, LAW_STICK, LAW_SLIDE };

/* The direction a landing tries to slide in first: the slip's before it, or with du = 0 against the sticking
 * impulse push = P_t. */
static int slide_first(double du, double push)
{
    if (du != 0.0)
        return du > 0.0 ? 1 : -1;
    return push > 0.0 ? -1 : 1;
}

/* The flying state about the other corner: (u, v, du, dv) <- flight_corner, s <- -s (theta, q, their rates
 * unchanged). */
static void corner_switch(run *r, const double *on)
{
    double c[4];
    model_flight_corner((double)r->phase, r->y, 0.0, 0.0, r->k->p, on, r->y[NY], r->y[NY + 2], r->y[NY + 1],
                        r->y[NY + 3], c);
    r->y[NY] = c[0];
    r->y[NY + 2] = c[1];
    r->y[NY + 1] = c[2];
    r->y[NY + 3] = c[3];
    r->phase = -r->phase;
}

/* The reference corner lands on a floor without friction (mu_s = inf) where the sticking impulse (out, from
 * landing_stick) would pull, P_n <= 0: the cone of the floor's impulses is the half-plane P_n >= 0, and the
 * plastic landing is the tangential impulse alone, which stops the slip (du+ = 0) and lifts the corner
 * (dv+ = dv - W_nt du / W_tt > 0 exactly where the sticking P_n < 0; docs/model.md section 16). Built from the
 * sticking and the frictionless landings (landing_slide at mu_slip = 0): the velocities after a landing are
 * linear in its impulse; numpy_backend's tangential_landing. out: dq+, du+, dv+, P_t, P_n; 0 where it does not
 * lift the corner. */
static int tangential_landing(const run *r, const double *on, double *out)
{
    double free[NQ + 4], before[NQ + 2], a_n[NQ + 2], a_t[NQ + 2], p_t;
    const double s = (double)r->phase, du = r->y[NY + 1], dv = r->y[NY + 3];
    const double P_t = out[NQ + 2], P_n = out[NQ + 3];
    int j;
    model_landing_slide(s, r->y, 0.0, 0.0, r->k->p, on, du, dv, r->c->e_n, 0.0, free);
    if (!(free[NQ + 3] > 0.0) || P_t == 0.0)
        return 0;
    for (j = 0; j < NQ; ++j)
        before[j] = r->y[NQ + j];
    before[NQ] = du;
    before[NQ + 1] = dv;
    for (j = 0; j < NQ + 2; ++j) {
        a_n[j] = (free[j] - before[j]) / free[NQ + 3];
        a_t[j] = (out[j] - before[j] - a_n[j] * P_n) / P_t;
    }
    p_t = -du / a_t[NQ];
    for (j = 0; j < NQ + 2; ++j)
        out[j] = before[j] + a_t[j] * p_t;
    out[NQ] = 0.0;
    out[NQ + 2] = p_t;
    out[NQ + 3] = 0.0;
    return out[NQ + 1] >= 0.0;
}

/* The landing of the reference corner alone (landing_law): sticks if the floor holds it, P_n > 0 and
 * |P_t| <= mu_s P_n; else slides in the direction sigma in which the slip keeps its sign through it, with
 * P_n > 0; else jams. out: dq+, du+, dv+, P_t, P_n (NQ + 4). */
static int law_corner(const run *r, const double *on, double *out, int *sigma)
{
    const double s = (double)r->phase, du = r->y[NY + 1], dv = r->y[NY + 3];
    int i, first;
    model_landing_stick(s, r->y, 0.0, 0.0, r->k->p, on, du, dv, r->c->e_n, out);
    if (out[NQ + 3] > 0.0 && (!r->friction || fabs(out[NQ + 2]) <= r->c->mu_s * out[NQ + 3]))
        return LAW_STICK;
    if (!r->friction)
        return tangential_landing(r, on, out) ? LAW_STICK : LAW_JAM;
    first = slide_first(du, out[NQ + 2]);
    for (i = 0; i < 2; ++i) {
        const int sg = i == 0 ? first : -first;
        model_landing_slide(s, r->y, 0.0, 0.0, r->k->p, on, du, dv, r->c->e_n, sg * r->c->mu_k, out);
        if (out[NQ + 3] > 0.0 && sg * du >= 0.0 && sg * out[NQ] >= 0.0) {
            *sigma = sg;
            return LAW_SLIDE;
        }
    }
    return LAW_JAM;
}

/* The flat landing on both corners at theta = 0 (numpy_backend's flat_landing): the law the floor allows,
 * stuck if |P_t| <= mu_s (P_s + P_o), else sliding in the direction sigma (slide_first first) with sigma du >= 0
 * before and after; under it both corners push (P_s, P_o >= 0): that law; one would pull: the other lands alone,
 * *alone the corner that lands (+1: s, -1: -s) and LAW_JAM returned; else (no law, both pull) LAW_JAM with
 * *alone 0. out: dq+, du+, dv+, P_t, P_s, P_o (NQ + 5). */
static int law_flat(const run *r, const double *on, double *out, int *sigma, int *alone)
{
    const double s = (double)r->phase, du = r->y[NY + 1], dv = r->y[NY + 3];
    int i, first, law = LAW_JAM;
    *alone = 0;
    model_flat_landing_stick(s, r->y, 0.0, 0.0, r->k->p, on, du, dv, r->c->e_n, out);
    if (fabs(out[NQ + 2]) <= r->c->mu_s * (out[NQ + 3] + out[NQ + 4])) {
        law = LAW_STICK;
    } else if (r->friction) {
        first = slide_first(du, out[NQ + 2]);
        for (i = 0; i < 2 && law == LAW_JAM; ++i) {
            const int sg = i == 0 ? first : -first;
            model_flat_landing_slide(s, r->y, 0.0, 0.0, r->k->p, on, du, dv, r->c->e_n, sg * r->c->mu_k, out);
            if (sg * du >= 0.0 && sg * out[NQ] >= 0.0) {
                law = LAW_SLIDE;
                *sigma = sg;
            }
        }
    }
    if (law == LAW_JAM || (out[NQ + 3] >= 0.0 && out[NQ + 4] >= 0.0))
        return law;
    if (!(out[NQ + 3] < 0.0 && out[NQ + 4] < 0.0))
        *alone = out[NQ + 4] < 0.0 ? 1 : -1;
    *sigma = 0;
    return LAW_JAM;
}

/* The landing of the corner s (other = 0) or -s (other = 1) at the state r->y (docs/model.md section 16,
 * rocking/reference/flight.py landing_law): the new velocities, and where the table leads: the phase on the
 * floor, on in flight where the corner bounces (dv after it above the speed of a corner turning at
 * dtheta_rest), or the end jammed. Returns 1 where the run ends. */
static int landing(run *r, int other)
{
    double on[2 * MAX_STOP_SIDES], out[NQ + 5], before[NA];
    const double *inputs = MODEL_NSTOPS > 0 ? on : NULL;
    int law, sigma = 0, alone = 0, flat = 0, rests = 0, guard, ended, s;
    memcpy(before, r->y, sizeof before);
    regime_inputs(r->k, on);
    if (other)
        corner_switch(r, inputs);
    r->y[NY + 2] = 0.0;
    if (fabs(sin(r->y[0])) <= ROCKING_FLAT_LANDING) {
        r->y[0] = 0.0;
        law = law_flat(r, inputs, out, &sigma, &alone);
        flat = law != LAW_JAM;
        if (alone < 0)
            corner_switch(r, inputs);
        if (alone != 0)
            law = law_corner(r, inputs, out, &sigma);
    } else {
        law = law_corner(r, inputs, out, &sigma);
    }
    if (law == LAW_JAM) {
        guard = PHASE_GUARD_JAMS;
    } else {
        memcpy(r->y + NQ, out, NQ * sizeof *out);
        r->y[NY + 1] = out[NQ];
        r->y[NY + 3] = out[NQ + 1];
        if (r->y[NY + 3] > r->c->dtheta_rest * r->base / 2.0) {
            guard = PHASE_GUARD_BOUNCES; /* the flight goes on (one flight: no takeoff) */
        } else {
            r->y[NY + 3] = 0.0;
            r->res->flight_time += r->t - r->t_takeoff;
            /* A corner landing alone at theta = 0 below dtheta_rest rests on the base (rule 2's snap below). */
            rests = r->y[0] == 0.0 && (flat || fabs(r->y[NQ]) < r->c->dtheta_rest);
            guard = rests ? (law == LAW_STICK ? PHASE_GUARD_RESTS : PHASE_GUARD_RESTS_SLIDING)
                          : (law == LAW_STICK ? PHASE_GUARD_ROCKS : PHASE_GUARD_ROCKS_SLIDING);
        }
    }
    s = r->phase;
    r->res->u_max = max2(r->res->u_max, fabs(r->y[NY])); /* the corner that lands: its own u */
    ended = enter(r, phase_next(PHASE_FLIGHT, PHASE_EVENT_LANDING, guard), s, sigma);
    if (ended) /* jammed: the run ends in flight (simulate_one counts its time) */
        return 1;
    if (rests && !flat)
        rest_snap(r, about(r->o.k, (double)s));
#if MODEL_NSTOPS > 0
    /* The velocities jumped: the pads' memory and regime follow the state (rule 6). */
    stop_memory_jump(r->k, before, r->y);
    stops_read(r);
#endif
    return 0;
}
#endif

/* The first extremum of a periodic shape after t: omega_g t + phase = pi/2 + k pi
 * (the one-sine: phase psi; the one-cosine: phase pi/2). The same operations
 * as numpy_backend.periodic_extremum. */
static double next_periodic_extremum(double w, double phase, double t)
{
    double k;
    int i;
    k = (w * t + phase - HALF_PI) / PI;
    k = w > 0.0 ? ceil(k) : floor(k);
    for (i = 0; i < 4; ++i) { /* rounding: the first or the second candidate */
        const double tk = (HALF_PI + k * PI - phase) / w;
        if (tk > t)
            return tk;
        k += w > 0.0 ? 1.0 : -1.0;
    }
    return INFINITY; /* not reached */
}

/* The first extremum of ag after t (rule 3): closed forms for the one-sine and
 * the one-cosine (with a vertical lead, also at the listed offsets of the
 * uplift margins' extrema, docs/model.md section 14), the listed extrema
 * (phase units) of the Ricker wavelets and the Mavroeidis-Papageorgiou pulse
 * (with a vertical lead, those of the margins too); infinity for a constant ground
 * acceleration, and for a sampled motion, whose every step ends at a sample
 * time. The same operations as numpy_backend.next_extremum. */
static double next_extremum(const rocking_case *c, double t)
{
    const double w = c->omega_g;
    int64_t i;
    if (!(w != 0.0) || c->a_g == 0.0)
        return INFINITY;
    switch (c->motion) {
    case ROCKING_MOTION_SINE:
    case ROCKING_MOTION_COSINE: {
        /* A vertical lead lists the uplift margins' extrema as offsets of the sine's argument, mod pi. */
        const double phase = c->motion == ROCKING_MOTION_SINE ? c->psi : HALF_PI;
        double tk = next_periodic_extremum(w, phase, t);
        for (i = 0; i < c->n_extrema; ++i)
            tk = fmin(tk, next_periodic_extremum(w, phase + HALF_PI - c->extrema[i], t));
        return tk;
    }
    case ROCKING_MOTION_SAMPLED:
        return INFINITY;
    default:
        for (i = 0; i < c->n_extrema; ++i) {
            const double tk = c->t_c + c->extrema[i] / w;
            if (tk > t)
                return tk;
        }
        return INFINITY;
    }
}

/* The whole run: docs/simulation.md, "Phases" and "End". */
static void phase_machine(run *r)
{
    const rocking_case *c = r->c;
    /* A model with flight follows it: t_flight ends nothing (docs/model.md section 16). */
    const double t_flight = FLIGHT ? INFINITY : c->t_flight;
    int skip_uplift_check = 0, skip_slip_check = 0;
    for (;;) {
        double t_bound;
        int ended;
        record(r, r->t, r->y, r->phase);
        if (r->t >= t_flight) { /* the base may leave the ground: out of scope (docs/model.md section 14) */
            r->res->status = ROCKING_FLIGHT;
            return;
        }
        if (r->t >= c->t_max) {
            r->res->status = r->flying ? ROCKING_T_MAX : safe_at_t_max(r);
            return;
        }
#if MODEL_NSTOPS > 0
        stops_read(r);
#endif
#ifdef MODEL_FLIGHT
        /* N <= 0 where full contact starts: the block takes off at once, before any uplift (a pivot needs the
         * floor to push); a rocking phase checks it where its segment starts (run_segment). */
        if (r->phase == 0 && !r->flying && !r->skip_lift_check && (r->friction || (r->t < c->t_p && c->a_v != 0.0)) &&
            lift_off_at_start(r)) {
            if (lift_off_counted(r, 0.0))
                return;
            continue;
        }
#endif
        if (r->phase == 0) {
            const int s = skip_uplift_check ? 0 : uplift_at_start(r);
            skip_uplift_check = 0;
            if (s != 0) { /* already above a threshold: uplift at this very instant */
                r->res->uplifts += 1;
                if (enter(r, phase_next(phase_code(r, 0, r->sigma), PHASE_EVENT_UPLIFT, PHASE_GUARD_ALWAYS), s, r->sigma))
                    return;
                r->safe = 0;
                if (events_exhausted(r)) {
                    r->res->status = ROCKING_MAX_EVENTS;
                    return;
                }
                continue;
            }
        }
#ifdef MODEL_FRICTION
        if (r->friction && !r->flying) {
            const int sigma = r->sigma;
            if (floor_at_start(r, !skip_slip_check))
                return;
            skip_slip_check = 0;
            if (r->flying) { /* N <= 0 at the start: it took off */
                if (events_exhausted(r)) {
                    r->res->status = ROCKING_MAX_EVENTS;
                    return;
                }
                continue;
            }
            if (r->sigma != sigma)
                continue;
        }
#else
        (void)skip_slip_check;
#endif
        if (r->phase == 0 && r->sigma == 0) {
            if (r->t >= c->t_p) {
                const double energy = energy_above_rest(r);
                /* For the bare block E(y) = E(0) in full contact: rest at once. */
                if (energy < c->energy_rest) {
                    r->res->status = ROCKING_REST;
                    return;
                }
                if (verdict_final(r)) {
                    r->res->status = ROCKING_BOUNDED;
                    return;
                }
                /* Below the uplift energy the block can never lift again: only
                 * the damper's stroke is left to settle (rule 4). */
                if (r->early && (r->safe || (energy < r->ec.energy_safe && stops_clear(r)))) {
                    if (settled_at_once(r)) {
                        r->res->status = ROCKING_REST;
                        return;
                    }
                    r->safe = 1;
                }
            }
        }
        /* Every segment stops at the pulse's end: no step straddles its kink. */
        t_bound = r->t < c->t_p ? fmin(fmin(c->t_p, c->t_max), t_flight) : c->t_max;
        /* In full contact also at the extrema of ag: no uplift is stepped over (rule 3). */
        if (r->phase == 0 && r->t < c->t_p)
            t_bound = fmin(t_bound, next_extremum(c, r->t));
        ended = run_segment(r, t_bound);
        record(r, r->t, r->y, r->phase);
#ifdef MODEL_FRICTION
        /* du keeps its sign in a sliding segment, so |u| is largest at one of its ends: the largest |u| at every
         * step end (a stuck segment's u is its start's, the end of the segment before). */
        if (r->sigma != 0 || r->flying) /* in flight between the located extrema of u (EV_U_PEAK) */
            r->res->u_max = max2(r->res->u_max, fabs(r->y[NY]));
#endif
        if (gap_side(ended) >= 0) { /* a breakpoint: the same phase restarts with the bumper on or off */
            int stop_on[MAX_STOP_SIDES];
            memcpy(stop_on, r->k->stop_on, sizeof stop_on);
            stop_on[gap_side(ended)] = ended < EV_GAP_OPEN;
            if (ended < EV_GAP_OPEN)
                stop_memory_record(r->k, r->y, gap_side(ended), 0);
            constants_switch(r->k, &r->regimes, stop_on);
            r->res->stop_contacts += ended < EV_GAP_OPEN;
            continue;
        }
        switch (ended) {
        case SEG_BOUND:
            if (t_bound == c->t_max) {
                r->res->status = r->flying ? ROCKING_T_MAX : safe_at_t_max(r);
                return;
            }
            break; /* a breakpoint: the same phase restarts from there */
        case SEG_FAILED:
            r->res->status = ROCKING_FAILED;
            return;
        case SEG_MAX_STEPS:
            r->res->status = ROCKING_MAX_STEPS;
            return;
        case SEG_STOPPED:
            r->res->status = ROCKING_STOPPED;
            return;
        case SEG_NO_LIFT:
            /* A grazing uplift: the block cannot rise, it stays on its base (the
             * uplift stays counted). u_s is still barely positive: the start
             * check of the contact phase would lift it again, forever. */
            r->y[0] = r->y[NQ] = 0.0;
            r->phase = 0;
            skip_uplift_check = 1;
            break;
#ifdef MODEL_FLIGHT
        case SEG_NO_TAKEOFF:
            lift_off_grazing(r);
            break;
#endif
        case SEG_NO_SLIP:
            /* A grazing slip: the base cannot move against F, the contact stays stuck; not a slip episode.
             * |F| is still barely above mu_s N: the start check would slip it again, forever. */
            r->sigma = 0;
            r->res->slides -= 1;
            skip_slip_check = 1;
            break;
        case EV_UPLIFT_A:
        case EV_UPLIFT_A_PRIME:
        case EV_SLIDE_UPLIFT_A:
        case EV_SLIDE_UPLIFT_A_PRIME:
            r->res->uplifts += 1;
            if (enter(r, phase_next(phase_code(r, 0, r->sigma), PHASE_EVENT_UPLIFT, PHASE_GUARD_ALWAYS), ended == EV_UPLIFT_A || ended == EV_SLIDE_UPLIFT_A ? 1 : -1,
                      r->sigma))
                return;
            r->safe = 0; /* not reached below the uplift energy; kept consistent if it were */
            if (events_exhausted(r)) {
                r->res->status = ROCKING_MAX_EVENTS;
                return;
            }
            break;
        case EV_IMPACT:
            if (impact(r))
                return;
            if (events_exhausted(r)) {
                r->res->status = ROCKING_MAX_EVENTS;
                return;
            }
            if (r->phase != 0 && verdict_final(r)) {
                r->res->status = ROCKING_BOUNDED;
                return;
            }
            break;
        case EV_OVERTURN:
        case EV_FLIGHT_OVERTURN:
            r->res->overturned = 1;
            r->res->t_overturn = r->t;
            enter(r, phase_next(phase_current(r), PHASE_EVENT_OVERTURN, PHASE_GUARD_ALWAYS), r->phase, r->sigma);
            return;
#ifdef MODEL_FRICTION
        case EV_SLIP:
            if (slip_starts(r))
                return;
            break;
        case EV_STOP:
            if (slip_stops(r))
                return;
            break;
        case EV_LIFT_OFF: /* at a segment's start too (run_segment), where no step was taken: d.h is 0 */
            if (lift_off_counted(r, r->d.h))
                return;
            break;
#endif
#ifdef MODEL_FLIGHT
        case EV_LANDING_S:
        case EV_LANDING_O:
            if (landing(r, ended == EV_LANDING_O))
                return;
            if (events_exhausted(r)) {
                r->res->status = ROCKING_MAX_EVENTS;
                return;
            }
            break;
#endif
        case EV_REST:
        case EV_SETTLED:
            r->res->status = ROCKING_REST;
            return;
        case EV_SAFE:
            r->safe = stops_clear(r); /* the next contact phase settles (not rechecked: E is at the bound) */
            break;
        default:
            r->res->status = ROCKING_FAILED; /* not reached: every terminal event is handled */
            return;
        }
    }
}

/* The base width B [m]: the height of the corner -s above the corner s of a block turned by pi/2 (generated
 * corner_heights; the model header names no parameter B). 0 without flight. */
static double flight_base_width(const constants *k)
{
#ifdef MODEL_FLIGHT
    double y[NY] = {0.0}, h[2], on[2 * MAX_STOP_SIDES];
    y[0] = HALF_PI;
    regime_inputs(k, on);
    model_corner_heights(1.0, y, 0.0, 0.0, k->p, MODEL_NSTOPS > 0 ? on : NULL, 0.0, h);
    return h[1];
#else
    (void)k;
    return 0.0;
#endif
}

/* The initial state: at rest, or a valid (y0, phase0). Returns 0 or -1. */
static int initial_state(const rocking_case *c, double *y, int *phase)
{
    int i;
    *phase = c->phase0;
    memset(y, 0, NA * sizeof *y); /* a run starts with the contact stuck, u = 0 */
    if (c->y0 == NULL)
        return *phase == 0 ? 0 : -1;
    for (i = 0; i < NY; ++i) {
        if (!isfinite(c->y0[i]))
            return -1;
        y[i] = c->y0[i];
    }
    if (*phase == 0)
        return (y[0] == 0.0 && y[NQ] == 0.0) ? 0 : -1;
    if (*phase != 1 && *phase != -1)
        return -1;
    /* s theta >= 0; from theta = 0 the block must move towards s theta > 0. */
    return (*phase * y[0] >= 0.0 && !(y[0] == 0.0 && *phase * y[NQ] < 0.0)) ? 0 : -1;
}

/* What the motion's family reads is there (rocking.sim.problem checks it before a call). */
static int pulse_valid(const rocking_case *c)
{
    if (c->motion < ROCKING_MOTION_SINE || c->motion > ROCKING_MOTION_SAMPLED)
        return 0;
    if (c->n_extrema < 0 || (c->n_extrema > 0 && c->extrema == NULL))
        return 0;
    if (c->motion == ROCKING_MOTION_SAMPLED)
        return c->samples != NULL && c->n_samples >= 2 && c->pulse_dt > 0.0;
    return 1;
}

/* memo holds what the parameters p prepare (memo may be NULL). */
static int memo_holds(const memo_prepared *memo, const double *p)
{
    return memo != NULL && memo->have && memcmp(memo->p, p, sizeof memo->p) == 0;
}

/* constants_prepare(k, p, clear) from memo, which holds p's. */
static void constants_known(constants *k, const double *p, const int *clear, const memo_prepared *memo)
{
    memcpy(k->stop_on, clear, sizeof k->stop_on);
    k->p = p;
    memcpy(k->about, memo->about, sizeof k->about);
}

static int64_t simulate_one(const double *p, const rocking_case *c, rocking_result *out, rocking_history *history,
                            const rocking_control *control, struct lane *lane, memo_prepared *memo)
{
    run r;
    constants k;
    const double zeros[NY] = {0.0};
    const int clear[MAX_STOP_SIDES] = {0};
    int stop_on[MAX_STOP_SIDES], i;
    double reach = INFINITY; /* pad_reach; no stops: no bound */
    const int known = memo_holds(memo, p);

    out->status = ROCKING_FAILED;
    out->overturned = 0;
    out->impacts = out->uplifts = 0;
    out->t_overturn = out->t_critical = NAN;
    out->theta_max = out->x_max = 0.0;
    out->t_end = 0.0;
    out->stop_contacts = 0;
    out->bumper_force_max = 0.0;
    out->u_max = out->u_end = 0.0;
    out->slides = 0;
    out->flight_time = out->jump_max = 0.0;
    out->flights = 0;

    r.c = c;
    r.tol.rtol = c->rtol;
    memcpy(r.atol, c->atol, NY * sizeof *c->atol);
#ifdef MODEL_FRICTION
    r.atol[NY] = c->atol[0]; /* u and du: the tolerances of theta and dtheta (docs/simulation.md, "Phases") */
    r.atol[NY + 1] = c->atol[NQ];
    r.friction = isfinite(c->mu_s);
#else
    r.friction = 0;
#endif
#ifdef MODEL_FLIGHT
    r.atol[NY + 2] = c->atol[0]; /* v and dv: those of u and du */
    r.atol[NY + 3] = c->atol[NQ];
#endif
    r.tol.atol = r.atol;
    r.sigma = 0;
    for (i = 0; i < 4; ++i) { /* without friction a run never slides: the stuck phases alone */
        const int code = r.codes[i / 2][i % 2] = phase_of(i / 2, i % 2);
        if (r.friction || i % 2 == 0)
            r.exits[code] = phase_exit_events(code);
    }
    r.exits[PHASE_FLIGHT] = FLIGHT ? phase_exit_events(PHASE_FLIGHT) : 0u;
    r.flying = 0;
    r.t_takeoff = 0.0;
    r.lift_phase = r.lift_sigma = r.skip_lift_check = 0;
    memset(k.memory, 0, sizeof k.memory);
    if (known)
        constants_known(&k, p, clear, memo);
    else
        constants_prepare(&k, p, clear);
    if (!known && memo != NULL) {
        memcpy(memo->p, p, sizeof memo->p);
        memcpy(memo->about, k.about, sizeof memo->about);
        memo->have = 0; /* until its bound too is read */
    }
    stop_memory_start(&k, zeros, clear); /* E(0) in the regime of the rest state, its memory too */
    r.k = &k;
    r.o.k = &k;
    memset(r.regimes.ready, 0, sizeof r.regimes.ready);
    regime_keep(&r.regimes, &k); /* the rest state's regime, where a released pad lets the mass go */
    r.o.phase = 0;
    r.o.sigma = 0;
    r.o.flying = 0;
    r.o.ny = NY;
    r.o.mu_slip = 0.0;
    r.o.pulse_on = 1;
    r.o.vertical = 0;
    r.o.rhs = ode_rhs_kind(&r.o);
    r.o.c = c;
    r.o.piece = 0.0;
    r.o.memo_t = NAN;
    r.o.lane = lane;
    r.ec.o = &r.o;
    /* In full contact the energy does not depend on the pivot: E(0) with s = +1,
     * in the regime of the rest state. */
    stop_regime(&k, zeros, stop_on);
    constants_regime(&k, stop_on);
    r.ec.energy_zero = known ? memo->energy_zero : model_energy_prepared(zeros, 0.0, about(&k, 1.0));
    if (!known && memo != NULL)
        memo->energy_zero = r.ec.energy_zero;
    r.ec.energy_rest = c->energy_rest;
    r.ec.mu_s = c->mu_s;
    if (r.friction) { /* numpy_backend's SLIDE_UPLIFT_ROUNDING: 64 eps of the weight's moment about each corner */
        r.ec.slide_uplift_floor[0] = 64.0 * DBL_EPSILON * fabs(model_uplift_prepared(zeros, 0.0, about(&k, 1.0)));
        r.ec.slide_uplift_floor[1] = 64.0 * DBL_EPSILON * fabs(model_uplift_prepared(zeros, 0.0, about(&k, -1.0)));
    }
    memset(&r.ec.bound, 0, sizeof r.ec.bound); /* not ready: normal_bound off (a model without flight) */
    r.ec.bound_live = r.ec.bound_side = 0;
#ifdef MODEL_FLIGHT
    if (known) {
        r.ec.bound = memo->bound;
    } else {
        normal_bound_read(&r.ec.bound, &k);
        if (memo != NULL)
            memo->bound = r.ec.bound;
    }
#endif
    if (!known && memo != NULL) {
        memo->base = MODEL_NSTOPS == 0 ? flight_base_width(&k) : NAN;
        memo->have = 1;
    }
    r.ec.theta_max = &out->theta_max;
    r.ec.x_max = &out->x_max;
    r.ec.u_max = &out->u_max;
#if NQ > 1 && MODEL_NSTOPS > 0
    /* With stops, rest (rule 4) also needs the mass out of every pad's reach (NaN: no bound, energy_rest alone). */
    reach = pad_reach(&r);
    if (!isnan(reach))
        r.ec.energy_rest = fmin(c->energy_rest, reach);
#endif
    /* The settling of rule 4 assumes a stuck contact: none on a floor that can slip. */
    r.ec.energy_safe = c->early_rest && !r.friction ? safe_energy(&k, reach) : NAN;
    r.early = !isnan(r.ec.energy_safe);
    r.safe = 0;
    r.verdict = c->early_verdict != 0 && !r.friction; /* the energy does not bound the slip */
    r.bound_at[0] = r.bound_at[1] = r.least_tilt_at = NAN; /* no bound yet */
#if NQ > 1
    r.arcs_at = r.least_stroke_at = NAN;
#endif
    r.bound = -INFINITY;
    r.t = 0.0;
    r.t_start = r.h_first = 0.0;
    r.res = out;
    r.stop = control != NULL ? control->stop : NULL;
    r.velocity_law = control != NULL ? control->velocity_law : NULL;
    r.samples = 0;
    r.d.evaluations = 0;
    r.hist = history;
    r.n_rec = 0;
    r.last_t = 0.0;
    r.last_phase = r.last_sigma = r.last_flying = 0;
    r.next_sample = 0.0;
    if (!pulse_valid(c) || initial_state(c, r.y, &r.phase) != 0)
        return -1;
    stop_memory_start(&k, r.y, clear); /* a contact in progress at the start starts there (docs/model.md 11) */
    stop_regime(&k, r.y, stop_on); /* the regime starts from the initial state (rule 6) */
    constants_regime(&k, stop_on);
    see_state(&r, r.y, 0, NULL);

    /* Without stops the width depends on the parameters alone (with them, on the regime's inputs too). */
    r.base = MODEL_NSTOPS == 0 && memo != NULL ? memo->base : flight_base_width(&k);
    phase_machine(&r);
    out->t_end = r.t;
    if (r.flying) /* the run ended in flight */
        out->flight_time += r.t - r.t_takeoff;
#ifdef MODEL_FRICTION
    out->u_end = r.y[NY];
#endif
    record(&r, r.t, r.y, r.phase);
    return r.n_rec;
}

#include "lanes.c" /* the batch in lanes */

/* ------------------------------------------------------------------------ */
/* 5. Entry points                                                           */
/* ------------------------------------------------------------------------ */

int rocking_model_nq(void) { return MODEL_NQ; }
int rocking_model_ny(void) { return MODEL_NY; }
int rocking_model_np(void) { return MODEL_NP; }
int rocking_api_version(void) { return ROCKING_SIM_API_VERSION; }

void rocking_layout(int64_t *case_offsets, int64_t *result_offsets)
{
    int64_t i = 0;
#define OFFSET(f) case_offsets[i++] = (int64_t)offsetof(rocking_case, f);
    ROCKING_CASE_FIELDS(OFFSET)
#undef OFFSET
    case_offsets[i] = (int64_t)sizeof(rocking_case);
    i = 0;
#define OFFSET(f) result_offsets[i++] = (int64_t)offsetof(rocking_result, f);
    ROCKING_RESULT_FIELDS(OFFSET)
#undef OFFSET
    result_offsets[i] = (int64_t)sizeof(rocking_result);
}

void rocking_constants(double *out)
{
    int i = 0;
#define VALUE(c) out[i++] = (double)(c);
    ROCKING_CONSTANTS(VALUE)
#undef VALUE
}

int64_t rocking_simulate(const double *p, const rocking_case *c, rocking_result *out, rocking_history *history,
                         const rocking_control *control)
{
    return simulate_one(p, c, out, history, control, NULL, NULL);
}

void rocking_simulate_batch(int64_t n, const double *p, const rocking_case *cases, rocking_result *out,
                            const rocking_control *control)
{
    rocking_simulate_batch_lanes(n, p, cases, out, control, 1); /* lanes.c */
}

/* ------------------------------------------------------------------------- */
/* 6. Ctrl-C                                                                  */
/* ------------------------------------------------------------------------- */

static volatile int32_t *volatile sigint_stop = NULL;
static volatile sig_atomic_t sigint_seen = 0;
#ifdef _WIN32
static void (*sigint_saved)(int) = SIG_DFL;
#else
static struct sigaction sigint_saved;
#endif

static void sigint_handler(int signum)
{
    (void)signum;
    sigint_seen = 1;
    if (sigint_stop != NULL)
        *sigint_stop = 1;
}

int rocking_sigint_catch(volatile int32_t *stop)
{
    sigint_seen = 0;
    sigint_stop = stop;
#ifdef _WIN32
    sigint_saved = signal(SIGINT, sigint_handler);
    if (sigint_saved == SIG_ERR || sigint_saved == SIG_IGN) {
        if (sigint_saved == SIG_IGN)
            signal(SIGINT, SIG_IGN);
        sigint_stop = NULL;
        return 0;
    }
    return 1;
#else
    struct sigaction act;
    if (sigaction(SIGINT, NULL, &sigint_saved) != 0 || sigint_saved.sa_handler == SIG_IGN) {
        sigint_stop = NULL; /* an ignored SIGINT stays ignored */
        return 0;
    }
    memset(&act, 0, sizeof act);
    act.sa_handler = sigint_handler;
    sigemptyset(&act.sa_mask);
    if (sigaction(SIGINT, &act, NULL) != 0) {
        sigint_stop = NULL;
        return 0;
    }
    return 1;
#endif
}

int rocking_sigint_release(void)
{
#ifdef _WIN32
    signal(SIGINT, sigint_saved);
#else
    sigaction(SIGINT, &sigint_saved, NULL);
#endif
    sigint_stop = NULL;
    return (int)sigint_seen;
}
