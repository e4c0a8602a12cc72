/* The C batch in lanes (lanes.h): included by sim.c after simulate_one, whose types and functions it uses.
 *
 * Each lane is a coroutine that runs simulate_one on a stack of its own. When its run needs the stages of
 * a step (dopri_step_of calls lanes_stages), the lane posts the request and switches to the next lane
 * (lane_next); the last lane of a round computes the stages of every lane over a vector (lanes_kernel.h)
 * and each goes on, in turn, with its scalar step-size control, events and phases until its next step.
 * A lane whose run ends takes the next case of the batch; with none left, it leaves the round.
 */
#include <stdlib.h>

#include "lanes.h"

/* x86-64 with the System V calling convention in ELF objects (Linux, the BSDs): the stack switch below. */
#if defined(__x86_64__) && defined(__ELF__) && (defined(__GNUC__) || defined(__clang__)) && defined(ROCKING_LANES_MODEL)
#include <immintrin.h>

#include ROCKING_LANES_MODEL
#endif
#ifndef LANES_MODEL
#define LANES_MODEL 0
#endif

/* The runs in flight at most: an AVX-512 vector of doubles. A batch runs as many as a call of its kernel computes
 * (a vector; SSE2: LANES_SSE2_GROUPS vectors side by side): more runs in flight, in turn over calls, cost more CPU
 * time (their states evict each other from the caches; measured on the bench map before the stacks were staggered:
 * 8 runs over AVX2 vectors of 4, 8 % more time, SSE2 with 4 or 8 runs in turn over vectors of 2, 4 % and 7 %). */
#define LANES_RUNS 8
/* The stack of a lane: simulate_one and the vector stages need tens of kB (a run, the constants of a model over
 * vectors); far more, of which the pages never touched cost nothing. */
#define LANES_STACK (1024 * 1024)
/* The tops of the lanes' stacks are this much apart beyond a multiple of LANES_STACK: the same frames of the lanes
 * (a run's state) then fall into different sets of the caches, not all into one (37 lines of 64 bytes: the tops
 * of 8 lanes on 8 different lines modulo 4 kB, the span of the first level's sets; bench map, AVX-512 vectors of
 * 8 runs: 9 % less time, AVX2 1 %). */
#define LANES_STAGGER (37 * 64)

typedef struct lanes lanes;

typedef struct lane {
    void *sp;      /* the stack pointer of the coroutine while it is suspended */
    lanes *owner;  /* the scheduler */
    int index;     /* its place in the round (lanes' active) */
    /* a request for the stages of a step (lanes_stages) and its answer, err */
    dopri *d;
    ode *o;
    const tolerance *tol;
    double h, t_new, *y_new, err;
    double power; /* err^ERROR_EXPONENT, computed with the stages over vectors (NAN: not) */
    unsigned segment; /* counts the segments of the lane's runs: a new one may have new constants */
} lane;

/* The vectors of a lanes_cache's data: the model's constants, the absolute and relative tolerances, the one-sine
 * pulse's amplitude, circular frequency and phase, and the masks of the lanes whose one-sine pulse acts, and of
 * those in full contact. */
enum { LC_CST = 0, LC_ATOL = NK, LC_RTOL = NK + NY, LC_A, LC_OMEGA, LC_PSI, LC_SINE, LC_CONTACT, LC_VECTORS };

/* The values of a segment of the runs of the lanes of a vector (the model's constants, the tolerances, the
 * pulse, full contact or not): the same over the segment, gathered into vectors when one of its lanes starts a
 * new one (lanes_kernel.h's refresh), not at every step. */
typedef struct lanes_cache {
    const lane *who[LANES_RUNS]; /* the lane of each element, and the segment its values are of */
    unsigned segment[LANES_RUNS];
    int other[LANES_RUNS]; /* the element's pulse acts and is not a one-sine */
    int any_contact, any_rocking, any_sine, any_other;
    double data[LC_VECTORS * LANES_RUNS] __attribute__((aligned(64))); /* LC_*, each LANES_RUNS doubles at most */
} lanes_cache;

/* The scalar stages and error estimate of a step (dopri_step_of's own). */
static double scalar_stages(dopri *d, ode *o, const tolerance *tol, double h, double t_new, double *y_new)
{
    dopri_stages(d, o, h, t_new, y_new);
    return dopri_error(d, tol, h, y_new, NY);
}

/* The scalar loop of rocking_simulate_batch: case i exactly as rocking_simulate runs it. */
static void batch_scalar(int64_t n, const double *p, const rocking_case *cases, rocking_result *out,
                         const rocking_control *control)
{
    memo_prepared memo = {0};
    int64_t i;
    for (i = 0; i < n; ++i) {
        if (control != NULL && control->stop != NULL && *control->stop != 0) {
            out[i].status = ROCKING_STOPPED; /* the rest of the batch is not run */
            continue;
        }
        simulate_one(p + i * MODEL_NP, cases + i, out + i, NULL, control, NULL, &memo);
    }
}

#if LANES_MODEL

/* ---- vector sin and cos ------------------------------------------------------------------------------ */

/* The kernels of fdlibm's k_sin.c and k_cos.c (sin and cos on [-pi/4, pi/4], error below one unit in the
 * last place) and the parts of pi/2 of its e_rem_pio2.c:
 *   Copyright (C) 1993 by Sun Microsystems, Inc. All rights reserved.
 *   Developed at SunPro, a Sun Microsystems, Inc. business.
 *   Permission to use, copy, modify, and distribute this software is freely granted, provided that this
 *   notice is preserved. */
#define LANES_S1 -1.66666666666666324348e-01
#define LANES_S2 8.33333333332248946124e-03
#define LANES_S3 -1.98412698298579493134e-04
#define LANES_S4 2.75573137070700676789e-06
#define LANES_S5 -2.50507602534068634195e-08
#define LANES_S6 1.58969099521155010221e-10
#define LANES_C1 4.16666666666666019037e-02
#define LANES_C2 -1.38888888888741095749e-03
#define LANES_C3 2.48015872894767294178e-05
#define LANES_C4 -2.75573143513906633035e-07
#define LANES_C5 2.08757232129817482790e-09
#define LANES_C6 -1.13596475577881948265e-11
#define LANES_INVPIO2 6.36619772367581382433e-01 /* 2 / pi */
#define LANES_PIO2_1 1.57079632673412561417e+00  /* the first 33 bits of pi/2 */
#define LANES_PIO2_2 6.07710050630396597660e-11  /* the next 33 bits */
#define LANES_PIO2_2T 2.02226624879595063154e-21 /* pi/2 - PIO2_1 - PIO2_2 */
/* Below pi/4: x 2/pi rounds to n = 0, and the reduction leaves x as it is. */
#define LANES_PIO4 0.785
/* 1.5 2^52: x + LANES_SHIFTER - LANES_SHIFTER rounds x to an integer, which the low bits of the sum hold. */
#define LANES_SHIFTER 6755399441055744.0
/* fdlibm's e_log.c (Lg1..Lg7, ln 2 in two parts) and e_exp.c (P1..P5, 1 / ln 2), same notice. */
#define LANES_LG1 6.666666666666735130e-01
#define LANES_LG2 3.999999999940941908e-01
#define LANES_LG3 2.857142874366239149e-01
#define LANES_LG4 2.222219843214978396e-01
#define LANES_LG5 1.818357216161805012e-01
#define LANES_LG6 1.531383769920937332e-01
#define LANES_LG7 1.479819860511658591e-01
#define LANES_LN2_HI 6.93147180369123816490e-01
#define LANES_LN2_LO 1.90821492927058770002e-10
#define LANES_INVLN2 1.44269504088896338700e+00
#define LANES_P1 1.66666666666666019037e-01
#define LANES_P2 -2.77777777770155933842e-03
#define LANES_P3 6.61375632143793436117e-05
#define LANES_P4 -1.65339022054652515390e-06
#define LANES_P5 4.13813679705723846039e-08
#define LANES_SQRT2 1.41421356237309504880
/* The bits of a double: its mantissa, all but its sign, those of 1.0 and of LANES_SHIFTER (below). */
#define LANES_MANTISSA 0x000fffffffffffffLL
#define LANES_MAGNITUDE 0x7fffffffffffffffLL
#define LANES_ONE_BITS 0x3ff0000000000000LL
#define LANES_SHIFTER_BITS 0x4338000000000000LL
/* Where n PIO2_1 and n PIO2_2 stay exact (|n| < 2^20) with a margin; larger arguments go to libm. */
#define LANES_TRIG_MAX 1.0e5

/* The constants of the vector functions that are not in the generated code, by name (LANES_<name>): each is
 * splatted over a vector in a table per width (lanes_kernel.h's LK), whose elements the compiler then reads as
 * operands from memory, rather than building each vector from its scalar at every use (SSE2: two instructions). */
#define LANES_CONSTANTS(X)                                                                                         \
    X(S1) X(S2) X(S3) X(S4) X(S5) X(S6) X(C1) X(C2) X(C3) X(C4) X(C5) X(C6) X(INVPIO2) X(PIO2_1) X(PIO2_2)          \
    X(PIO2_2T) X(PIO4) X(TRIG_MAX) X(SHIFTER) X(LG1) X(LG2) X(LG3) X(LG4) X(LG5) X(LG6) X(LG7) X(LN2_HI) X(LN2_LO)   \
    X(INVLN2) X(P1) X(P2) X(P3) X(P4) X(P5) X(SQRT2) X(EXPONENT) X(NORMAL_MIN) X(NORMAL_MAX) X(HALF) X(ONE) X(TWO)
#define LANES_EXPONENT ERROR_EXPONENT
#define LANES_NORMAL_MIN DBL_MIN
#define LANES_NORMAL_MAX DBL_MAX
#define LANES_HALF 0.5
#define LANES_ONE 1.0
#define LANES_TWO 2.0
/* The same for the bit masks, a table of vectors of 64-bit integers (lanes_kernel.h's LM). */
#define LANES_MASKS(X) X(MANTISSA) X(MAGNITUDE) X(ONE_BITS) X(SHIFTER_BITS)
enum {
#define LANES_INDEX(name) LK_##name,
    LANES_CONSTANTS(LANES_INDEX)
#undef LANES_INDEX
    LK_COUNT
};
enum {
#define LANES_INDEX(name) LM_##name,
    LANES_MASKS(LANES_INDEX)
#undef LANES_INDEX
    LM_COUNT
};

/* ---- the kernels, one per vector width --------------------------------------------------------------- */

/* The vectors of 2 doubles (SSE2) a call of the kernel computes side by side: one stage's chain of operations
 * waits on the previous stage's, and the other vector's fill the wait (AVX2 and AVX-512: one vector a call). Two
 * vectors of 2 runs rather than one: the kernel's time per run about 9 % less, the scalar code's more (4 runs in
 * flight evict each other's state), in all 1 % less CPU time on the bench map (bench/compare.py, 20 paired runs,
 * ROCKING_LANES_ISA=sse2). */
#define LANES_SSE2_GROUPS 2

#define LW 2
#define LG LANES_SSE2_GROUPS
#define LTARGET "sse2"
#define LNAME(x) x##_sse2
#include "lanes_kernel.h"
#undef LW
#undef LG
#undef LTARGET
#undef LNAME

#define LW 4
#define LG 1
#define LTARGET "avx2"
#define LNAME(x) x##_avx2
#include "lanes_kernel.h"
#undef LW
#undef LG
#undef LTARGET
#undef LNAME

#define LW 8
#define LG 1
#define LTARGET "avx512f"
#define LNAME(x) x##_avx512
#include "lanes_kernel.h"
#undef LW
#undef LG
#undef LTARGET
#undef LNAME

typedef int (*lanes_kernel)(lane *const *ls, lanes_cache *caches);

/* ---- the coroutines (x86-64) ------------------------------------------------------------------------- */

/* Save the callee-saved registers on the current stack and its pointer into *save, then resume the stack `to`
 * saved the same way (or prepared by lane_start). MXCSR and the x87 control word, callee-saved too, are not
 * switched: every lane runs with the batch caller's, which no code changes across a switch (libm restores
 * what it sets inside a call). */
void rocking_lanes_switch(void **save, void *to) __attribute__((visibility("hidden")));
/* A new lane's first code: lane_main(r12), on the lane's stack. */
void rocking_lanes_start(void) __attribute__((visibility("hidden")));
__asm__(".pushsection .text\n"
        ".p2align 4\n"
        ".globl rocking_lanes_switch\n"
        ".hidden rocking_lanes_switch\n"
        ".type rocking_lanes_switch, @function\n"
        "rocking_lanes_switch:\n"
        "    pushq %rbp\n"
        "    pushq %rbx\n"
        "    pushq %r12\n"
        "    pushq %r13\n"
        "    pushq %r14\n"
        "    pushq %r15\n"
        "    movq %rsp, (%rdi)\n"
        "    movq %rsi, %rsp\n"
        "    popq %r15\n"
        "    popq %r14\n"
        "    popq %r13\n"
        "    popq %r12\n"
        "    popq %rbx\n"
        "    popq %rbp\n"
        "    ret\n"
        ".size rocking_lanes_switch, .-rocking_lanes_switch\n"
        ".p2align 4\n"
        ".globl rocking_lanes_start\n"
        ".hidden rocking_lanes_start\n"
        ".type rocking_lanes_start, @function\n"
        "rocking_lanes_start:\n"
        "    movq %r12, %rdi\n"
        "    callq *%r13\n"
        "    ud2\n"
        ".size rocking_lanes_start, .-rocking_lanes_start\n"
        ".popsection\n");

struct lanes {
    void *sp; /* the scheduler's stack pointer while a lane runs */
    int width;
    lanes_kernel kernel;
    lane lane[LANES_RUNS];
    /* The round: the lanes that still have a run (width at most), in the order they run; each posts its step (or
     * leaves), the last then serves them all. */
    lane *active[LANES_RUNS];
    int n_active;
    lanes_cache cache[LANES_SSE2_GROUPS]; /* those of each vector of a round */
    unsigned char *stacks;
    /* the batch */
    int64_t n, next;
    const double *p;
    const rocking_case *cases;
    rocking_result *out;
    const rocking_control *control;
    memo_prepared memo; /* shared by the lanes: a run reads it at its start, between two switches */
};

/* The next case of the batch b, or -1 if none is left. Cases read after the stop flag is set end as the scalar
 * loop leaves them. */
static int64_t lanes_take(lanes *b)
{
    while (b->next < b->n) {
        const int64_t i = b->next++;
        if (b->control == NULL || b->control->stop == NULL || *b->control->stop == 0)
            return i;
        b->out[i].status = ROCKING_STOPPED;
    }
    return -1;
}

/* The stages of every lane of the round over a vector (fewer lanes than its width: padded with the last again). */
static void lanes_serve(lanes *b)
{
    const int n = b->n_active;
    lane *padded[LANES_RUNS], *const *ls = b->active;
    int scalar, j;
    if (n < b->width) {
        for (j = 0; j < b->width; ++j)
            padded[j] = b->active[j < n ? j : n - 1];
        ls = padded;
    }
    scalar = b->kernel(ls, b->cache);
    for (j = 0; scalar != 0 && j < n; ++j)
        if (scalar >> j & 1) /* a sin or cos out of the vector functions' range: this step scalar */
            ls[j]->err = scalar_stages(ls[j]->d, ls[j]->o, ls[j]->tol, ls[j]->h, ls[j]->t_new, ls[j]->y_new);
}

/* Lane l has posted its step (lanes_stages) or left the round: run the lane at place `next` of the round; past
 * the last, serve the round and run its first lane (l itself: return at once); when none is left, back to the
 * caller of the batch. One switch per step of a lane, from lane to lane: a round ends in the vector stages, on
 * the stack of the lane that ends it. */
static void lane_next(lane *l, int next)
{
    lanes *b = l->owner;
    if (next < b->n_active) {
        rocking_lanes_switch(&l->sp, b->active[next]->sp);
        return;
    }
    if (b->n_active == 0) {
        rocking_lanes_switch(&l->sp, b->sp); /* not resumed again */
        return;
    }
    lanes_serve(b);
    if (b->active[0] != l)
        rocking_lanes_switch(&l->sp, b->active[0]->sp);
}

/* Lane l leaves the round of b: the lanes after it move up a place. */
static void lanes_leave(lanes *b, const lane *l)
{
    int j;
    for (j = l->index; j + 1 < b->n_active; ++j) {
        b->active[j] = b->active[j + 1];
        b->active[j]->index = j;
    }
    --b->n_active;
}

/* The coroutine of a lane: runs of the batch's cases, one after the other, until none is left. */
static void lane_main(lane *l)
{
    lanes *b = l->owner;
    int64_t i;
    while ((i = lanes_take(b)) >= 0)
        simulate_one(b->p + i * MODEL_NP, b->cases + i, b->out + i, NULL, b->control, l, &b->memo);
    lanes_leave(b, l);
    lane_next(l, l->index); /* the lane that took its place */
}

/* The first frame of lane l on its stack [stack, stack + size): what rocking_lanes_switch pops, then its
 * return into rocking_lanes_start, which calls lane_main(l) with the stack aligned as for a call (the stack
 * pointer at `top`, a multiple of 16, once all is popped). Its first switch starts it. */
static void lane_start(lane *l, unsigned char *stack, size_t size)
{
    uint64_t *top = (uint64_t *)(((uintptr_t)(stack + size)) & ~(uintptr_t)15);
    uint64_t *sp = top - 7; /* r15, r14, r13, r12, rbx, rbp, the return address */
    memset(sp, 0, 7 * sizeof *sp);
    sp[2] = (uint64_t)(uintptr_t)lane_main; /* r13 */
    sp[3] = (uint64_t)(uintptr_t)l;         /* r12 */
    sp[6] = (uint64_t)(uintptr_t)rocking_lanes_start;
    l->sp = sp;
}

/* The vector width a batch now uses (rocking_lanes). AVX2's 4 doubles where the CPU has it, AVX-512F's 8 only on
 * request: on the bench map 8 runs in flight over AVX-512 vectors took 1-7 % more CPU time than 4 over AVX2 vectors
 * in 8 of 9 runs, 1 % less in one (python bench/lanes.py; a Xeon with AVX-512 FP16): the kernel is the lesser part
 * of a step, and 8 runs' states fill more of the caches. The results are the same bits at every width. LLVM likewise prefers 256-bit vectors on Intel's AVX-512 server
 * cores (its X86.td: TuningPrefer256Bit in SKX's tuning). */
static int lanes_width(void)
{
    const char *on = getenv("ROCKING_LANES"), *isa = getenv("ROCKING_LANES_ISA");
    int cap = 4;
    if (on != NULL && strcmp(on, "0") == 0)
        return 0;
    if (isa != NULL && strcmp(isa, "sse2") == 0)
        cap = 2;
    else if (isa != NULL && strcmp(isa, "avx512") == 0)
        cap = 8;
    __builtin_cpu_init();
    if (cap >= 8 && __builtin_cpu_supports("avx512f"))
        return 8;
    if (cap >= 4 && __builtin_cpu_supports("avx2"))
        return 4;
    return 2;
}

/* Run the batch in lanes: 1, or 0 if it cannot (the lanes are off, or no memory for their stacks). Out of line:
 * bench/instructions.py counts the lanes' instructions from its entry. */
static NOINLINE int lanes_batch(int64_t n, const double *p, const rocking_case *cases, rocking_result *out,
                       const rocking_control *control)
{
    lanes b;
    int j, runs;
    b.width = lanes_width();
    if (b.width == 0 || n < 1)
        return 0;
    /* A batch of a single case too: each run's results do not depend on how a batch is cut. */
    b.kernel = b.width == 8 ? stages_avx512 : b.width == 4 ? stages_avx2 : stages_sse2;
    if (b.width == 2)
        b.width *= LANES_SSE2_GROUPS; /* the runs of a round */
    runs = n < b.width ? (int)n : b.width;
    b.stacks = malloc((size_t)runs * LANES_STACK);
    if (b.stacks == NULL)
        return 0;
    b.n = n;
    b.next = 0;
    b.p = p;
    b.cases = cases;
    b.out = out;
    b.control = control;
    b.memo.have = 0;
    b.n_active = runs;
    for (j = 0; j < LANES_SSE2_GROUPS; ++j)
        memset(b.cache[j].who, 0, sizeof b.cache[j].who); /* no lane yet */
    for (j = 0; j < runs; ++j) {
        b.lane[j].owner = &b;
        b.lane[j].segment = 0;
        b.lane[j].index = j;
        b.active[j] = &b.lane[j];
        lane_start(&b.lane[j], b.stacks + (size_t)j * LANES_STACK, LANES_STACK - (size_t)j * LANES_STAGGER);
    }
    rocking_lanes_switch(&b.sp, b.lane[0].sp); /* back when every lane has finished */
    free(b.stacks);
    return 1;
}

/* The stages of a step of the lane's run: over vectors with the other lanes' for a rocking phase or full contact
 * without a vertical component or a slide (full contact where the model's header has it), else scalar here. */
static double lanes_stages(dopri *d, ode *o, const tolerance *tol, double h, double t_new, double *y_new)
{
    lane *l = o->lane;
    const int contact = o->rhs == ODE_PULSE_CONTACT || o->rhs == ODE_FREE_CONTACT;
    if (!(o->rhs == ODE_PULSE_ROCKING || o->rhs == ODE_FREE_ROCKING || (LANES_CONTACT && contact)))
        return scalar_stages(d, o, tol, h, t_new, y_new);
    if (d->h == 0.0) /* a segment starts (dopri_start), or its last step was taken back (dopri_undo) */
        ++l->segment;
    l->d = d;
    l->o = o;
    l->tol = tol;
    l->h = h;
    l->t_new = t_new;
    l->y_new = y_new;
    l->power = NAN;
    lane_next(l, l->index + 1);
    return l->err;
}

/* err^ERROR_EXPONENT for the step whose error lanes_stages returned last: computed with its stages if they were
 * (the same err), else libm's. */
static double lanes_error_power(const lane *l, double err)
{
    return l->power == l->power && l->err == err ? l->power : pow(err, ERROR_EXPONENT);
}

int rocking_lanes(void)
{
    return lanes_width();
}

#else /* no lanes: every batch scalar */

static double lanes_stages(dopri *d, ode *o, const tolerance *tol, double h, double t_new, double *y_new)
{
    return scalar_stages(d, o, tol, h, t_new, y_new); /* not reached: no run has a lane */
}

static double lanes_error_power(const lane *l, double err)
{
    (void)l;
    return pow(err, ERROR_EXPONENT); /* not reached */
}

static int lanes_batch(int64_t n, const double *p, const rocking_case *cases, rocking_result *out,
                       const rocking_control *control)
{
    (void)n, (void)p, (void)cases, (void)out, (void)control;
    return 0;
}

int rocking_lanes(void)
{
    return 0;
}

#endif

void rocking_simulate_batch_lanes(int64_t n, const double *p, const rocking_case *cases, rocking_result *out,
                                  const rocking_control *control, int32_t on)
{
    if (on == 0 || !lanes_batch(n, p, cases, out, control))
        batch_scalar(n, p, cases, out, control);
}
