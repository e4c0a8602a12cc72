/* The stages of the lanes' steps over vectors of LW doubles, compiled for the instruction set LTARGET:
 * included by lanes.c once per width, with LW, LTARGET, LNAME (a suffix per width) and LG defined: the groups of
 * LW lanes a call computes side by side, stage by stage (LG LW lanes in all). */

#define VD LNAME(vd)
#define VL LNAME(vl)
#define LATTR static inline __attribute__((always_inline, target(LTARGET)))

typedef double VD __attribute__((vector_size(LW * 8)));
typedef int64_t VL __attribute__((vector_size(LW * 8)));

/* A vector of LW times c, as an initializer. */
#if LW == 2
#define LSPLAT(c) {c, c}
#elif LW == 4
#define LSPLAT(c) {c, c, c, c}
#else
#define LSPLAT(c) {c, c, c, c, c, c, c, c}
#endif

static const VD LNAME(constants)[LK_COUNT] = {
#define LANES_ROW(name) [LK_##name] = LSPLAT(LANES_##name),
    LANES_CONSTANTS(LANES_ROW)
#undef LANES_ROW
};
static const VL LNAME(masks)[LM_COUNT] = {
#define LANES_ROW(name) [LM_##name] = LSPLAT(LANES_##name),
    LANES_MASKS(LANES_ROW)
#undef LANES_ROW
};

/* The tables of constants (lanes.c's LANES_CONSTANTS, LANES_MASKS), their addresses hidden from the compiler: it
 * then reads the vectors from memory where they are used, instead of folding them back into scalars to splat at
 * each use. */
LATTR const VD *LNAME(table)(void)
{
    const VD *k = LNAME(constants);
    __asm__("" : "+r"(k));
    return k;
}

LATTR const VL *LNAME(mask_table)(void)
{
    const VL *m = LNAME(masks);
    __asm__("" : "+r"(m));
    return m;
}
#define LK(name) lk[LK_##name]
#define LM(name) lm[LM_##name]

/* Every element of a vector c. */
LATTR VD LNAME(splat)(double c)
{
    VD v;
    int j;
    for (j = 0; j < LW; ++j)
        v[j] = c;
    return v;
}

/* Whether every element of the mask m (0 or -1 each) is set: their sign bits at once. */
LATTR int LNAME(all)(VL m)
{
#if LW == 2
    return _mm_movemask_pd((__m128d)m) == 3;
#elif LW == 4
    return _mm256_movemask_pd((__m256d)m) == 15;
#else
    return _mm512_test_epi64_mask((__m512i)m, (__m512i)m) == 0xff;
#endif
}

/* fdlibm's kernels of sin and cos of r in [-pi/4, pi/4], elementwise (lanes.c). */
LATTR void LNAME(sincos_kernel)(VD r, VD *s, VD *c)
{
    const VD *lk = LNAME(table)();
    const VD z = r * r;
    const VD v = z * r;
    const VD ps = LK(S2) + z * (LK(S3) + z * (LK(S4) + z * (LK(S5) + z * LK(S6))));
    const VD pc = z * (LK(C1) + z * (LK(C2) + z * (LK(C3) + z * (LK(C4) + z * (LK(C5) + z * LK(C6))))));
    const VD hz = LK(HALF) * z;
    const VD w = LK(ONE) - hz;
    *s = r + v * (LK(S1) + z * ps);
    *c = w + (((LK(ONE) - w) - hz) + z * pc);
}

/* sin and cos of x, elementwise: x reduced to r in about [-pi/4, pi/4] by x - n pi/2 with pi/2 in three parts
 * of 33 bits (exact products for |n| < 2^20), then fdlibm's kernels (lanes.c). An element out of
 * [-LANES_TRIG_MAX, LANES_TRIG_MAX] (or not finite) clears its element of *inside: the caller then does
 * without these values. */
LATTR void LNAME(sincos)(VD x, VD *s, VD *c, VL *inside)
{
    const VD *lk = LNAME(table)();
    const VL *lm = LNAME(mask_table)();
    const VD shifted = x * LK(INVPIO2) + LK(SHIFTER);
    const VD n = shifted - LK(SHIFTER);
    const VL q = (VL)shifted; /* the low bits of the mantissa: n mod 4 */
    const VD r = ((x - n * LK(PIO2_1)) - n * LK(PIO2_2)) - n * LK(PIO2_2T);
    VD sin_r, cos_r;
    LNAME(sincos_kernel)(r, &sin_r, &cos_r);
    /* Quadrant n mod 4: (sin, cos) = (s_r, c_r), (c_r, -s_r), (-s_r, -c_r), (-c_r, s_r). */
    const VL odd = -(q & 1);
    const VL sbits = (odd & (VL)cos_r) | (~odd & (VL)sin_r);
    const VL cbits = (odd & (VL)sin_r) | (~odd & (VL)cos_r);
    *s = (VD)(sbits ^ ((q & 2) << 62));
    *c = (VD)(cbits ^ (((q + 1) & 2) << 62));
    /* |x| <= max, false for a NaN (and no negation of a mask, which SSE2 has no instruction for) */
    *inside &= (VD)((VL)x & LM(MAGNITUDE)) <= LK(TRIG_MAX);
}

/* x^ERROR_EXPONENT (the step-size control's power of the error) for x a positive normal double: fdlibm's log
 * and exp (lanes.c), a few units in the last place from libm's pow. Another x clears its element of *inside. */
LATTR VD LNAME(error_power)(VD x, VL *inside)
{
    const VD *lk = LNAME(table)();
    const VL *lm = LNAME(mask_table)();
    const VL bits = (VL)x;
    const VD m1 = (VD)((bits & LM(MANTISSA)) | LM(ONE_BITS)); /* x = 2^e m1, m1 in [1, 2) */
    const VL big = m1 > LK(SQRT2);                            /* then m in [sqrt(1/2), sqrt(2)) */
    const VD m = (VD)((big & (VL)(LK(HALF) * m1)) | (~big & (VL)m1));
    const VD e = (VD)((((bits >> 52) & 0x7ff) - 1023 - big) + LM(SHIFTER_BITS)) - LK(SHIFTER);
    const VD f = m - LK(ONE), s = f / (LK(TWO) + f), z = s * s, w = z * z;
    const VD r = z * (LK(LG1) + w * (LK(LG3) + w * (LK(LG5) + w * LK(LG7)))) + w * (LK(LG2) + w * (LK(LG4) + w * LK(LG6)));
    const VD hfsq = LK(HALF) * f * f;
    const VD y = LK(EXPONENT) * (e * LK(LN2_HI) - ((hfsq - (s * (hfsq + r) + e * LK(LN2_LO))) - f));
    /* exp(y) = 2^k exp(t), t = y - k ln 2 in [-ln(2)/2, ln(2)/2] */
    const VD shifted = y * LK(INVLN2) + LK(SHIFTER);
    const VD k = shifted - LK(SHIFTER);
    const VD hi = y - k * LK(LN2_HI), lo = k * LK(LN2_LO), t = hi - lo, tt = t * t;
    const VD c = t - tt * (LK(P1) + tt * (LK(P2) + tt * (LK(P3) + tt * (LK(P4) + tt * LK(P5)))));
    const VD et = LK(ONE) - ((lo - (t * c) / (LK(TWO) - c)) - hi);
    *inside &= (x >= LK(NORMAL_MIN)) & (x <= LK(NORMAL_MAX));
    return (VD)((VL)et + (((VL)shifted - LM(SHIFTER_BITS)) << 52));
}

/* sincos of the block's angle: within [-pi/4, pi/4] in every lane mostly, where the reduction leaves x as it is
 * (n = 0, r = x: the same bits) and is skipped. */
LATTR void LNAME(sincos_angle)(VD x, VD *s, VD *c, VL *inside)
{
    const VD *lk = LNAME(table)();
    const VL *lm = LNAME(mask_table)();
    if (LNAME(all)((VD)((VL)x & LM(MAGNITUDE)) <= LK(PIO4)))
        LNAME(sincos_kernel)(x, s, c);
    else
        LNAME(sincos)(x, s, c, inside);
}

/* The generated right-hand side's sincos: the mask of the arguments in range is the caller's `inside`. */
#define LANES_SINCOS(x, s, c) LNAME(sincos_angle)(x, s, c, inside)
LANES_DEFINE_RHS(LNAME(rocking_accel), LATTR, VL *inside)
#if LANES_CONTACT
LANES_DEFINE_CONTACT(LNAME(contact_accel), LATTR, VL *inside __attribute__((unused)))
#endif
#undef LANES_SINCOS

/* A vector of the LW lanes' values of E(j), j the lane: built from the scalars (no stores of single elements
 * followed by a load of the whole vector, which the CPU cannot forward). */
#if LW == 2
#define LGATHER(E) ((VD){E(0), E(1)})
#elif LW == 4
#define LGATHER(E) ((VD){E(0), E(1), E(2), E(3)})
#else
#define LGATHER(E) ((VD){E(0), E(1), E(2), E(3), E(4), E(5), E(6), E(7)})
#endif

/* The ground acceleration of each lane at its t: a one-sine pulse over vectors (ode_ag's operations), another
 * motion by ode_ag, 0 after the pulse. any_sine, any_other: the cache's flags, read once per step (ode_ag's
 * calls would make the compiler read them again at each stage). */
LATTR VD LNAME(ground)(lane *const *ls, const VD t, const int *other, int any_sine, int any_other, const VD *v,
                       VL *inside)
{
    VD ag = LNAME(splat)(0.0), s, c;
    int j;
    if (any_sine) {
        LNAME(sincos)(v[LC_OMEGA] * t + v[LC_PSI], &s, &c, inside);
        ag = (VD)((VL)(v[LC_A] * s) & (VL)v[LC_SINE]);
    }
    if (any_other)
        for (j = 0; j < LW; ++j)
            if (other[j])
                ag[j] = ode_ag(ls[j]->o, t[j]);
    return ag;
}

/* The square root of each element (correctly rounded, as libm's sqrt). */
LATTR VD LNAME(sqrt)(VD x)
{
#if LW == 2
    return (VD)_mm_sqrt_pd((__m128d)x);
#elif LW == 4
    return (VD)_mm256_sqrt_pd((__m256d)x);
#else
    return (VD)_mm512_sqrt_pd((__m512d)x);
#endif
}

/* The larger of a and b, elementwise: a > b ? a : b, the second operand where either is a NaN (maxpd's rule),
 * as dopri_error's scale takes it. */
LATTR VD LNAME(max)(VD a, VD b)
{
#if LW == 2
    return (VD)_mm_max_pd((__m128d)a, (__m128d)b);
#elif LW == 4
    return (VD)_mm256_max_pd((__m256d)a, (__m256d)b);
#else
    return (VD)_mm512_max_pd((__m512d)a, (__m512d)b);
#endif
}

/* Transposes of blocks of doubles: a lane's NY values are then stored or loaded 2 or 4 at a time, not element by
 * element (two instructions each). LBLOCK components at a time: LW x LW blocks for SSE2 and AVX2, for AVX-512
 * two 4 x 4 blocks, one per half of the vectors (lanes 0-3, 4-7). */
#if LW <= 4
#define LBLOCK LW
#else
#define LBLOCK 4

/* The 4 x 4 block a[0..3] transposed in place. */
LATTR void LNAME(transpose4)(__m256d *a)
{
    const __m256d t0 = _mm256_unpacklo_pd(a[0], a[1]), t1 = _mm256_unpackhi_pd(a[0], a[1]);
    const __m256d t2 = _mm256_unpacklo_pd(a[2], a[3]), t3 = _mm256_unpackhi_pd(a[2], a[3]);
    a[0] = _mm256_permute2f128_pd(t0, t2, 0x20);
    a[1] = _mm256_permute2f128_pd(t1, t3, 0x20);
    a[2] = _mm256_permute2f128_pd(t0, t2, 0x31);
    a[3] = _mm256_permute2f128_pd(t1, t3, 0x31);
}
#endif

/* out[j][i] = in[i][j] for i, j < LW (SSE2 and AVX2). */
LATTR void LNAME(transpose_block)(const VD *in, VD *out)
{
#if LW == 2
    typedef int64_t mask __attribute__((vector_size(16)));
    out[0] = __builtin_shuffle(in[0], in[1], (mask){0, 2});
    out[1] = __builtin_shuffle(in[0], in[1], (mask){1, 3});
#elif LW == 4
    typedef int64_t mask __attribute__((vector_size(32)));
    const VD t0 = __builtin_shuffle(in[0], in[1], (mask){0, 4, 2, 6});
    const VD t1 = __builtin_shuffle(in[0], in[1], (mask){1, 5, 3, 7});
    const VD t2 = __builtin_shuffle(in[2], in[3], (mask){0, 4, 2, 6});
    const VD t3 = __builtin_shuffle(in[2], in[3], (mask){1, 5, 3, 7});
    out[0] = __builtin_shuffle(t0, t2, (mask){0, 1, 4, 5});
    out[1] = __builtin_shuffle(t1, t3, (mask){0, 1, 4, 5});
    out[2] = __builtin_shuffle(t0, t2, (mask){2, 3, 6, 7});
    out[3] = __builtin_shuffle(t1, t3, (mask){2, 3, 6, 7});
#else
    (void)in, (void)out; /* AVX-512: transpose4 on each half */
#endif
}

/* rows[j][i] = cols[i][j] for the NY components i and the LW lanes j. */
LATTR void LNAME(store_rows)(const VD *cols, double *const *rows)
{
    int i = 0, j;
#pragma GCC unroll 8
    for (; i + LBLOCK <= NY; i += LBLOCK) {
#if LW == 8
        __m256d lo[4], hi[4];
#pragma GCC unroll 8
        for (j = 0; j < 4; ++j) {
            lo[j] = _mm512_castpd512_pd256((__m512d)cols[i + j]);
            hi[j] = _mm512_extractf64x4_pd((__m512d)cols[i + j], 1);
        }
        LNAME(transpose4)(lo);
        LNAME(transpose4)(hi);
#pragma GCC unroll 8
        for (j = 0; j < 4; ++j) {
            _mm256_storeu_pd(rows[j] + i, lo[j]);
            _mm256_storeu_pd(rows[4 + j] + i, hi[j]);
        }
#else
        VD block[LW];
        LNAME(transpose_block)(cols + i, block);
#pragma GCC unroll 8
        for (j = 0; j < LW; ++j)
            memcpy(rows[j] + i, &block[j], sizeof block[j]);
#endif
    }
#pragma GCC unroll 8
    for (; i < NY; ++i)
#pragma GCC unroll 8
        for (j = 0; j < LW; ++j)
            rows[j][i] = cols[i][j];
}

/* cols[i][j] = rows[j][i] for the NY components i and the LW lanes j. */
LATTR void LNAME(load_rows)(const double *const *rows, VD *cols)
{
    int i = 0, j;
#pragma GCC unroll 8
    for (; i + LBLOCK <= NY; i += LBLOCK) {
#if LW == 8
        __m256d lo[4], hi[4];
#pragma GCC unroll 8
        for (j = 0; j < 4; ++j) {
            lo[j] = _mm256_loadu_pd(rows[j] + i);
            hi[j] = _mm256_loadu_pd(rows[4 + j] + i);
        }
        LNAME(transpose4)(lo);
        LNAME(transpose4)(hi);
#pragma GCC unroll 8
        for (j = 0; j < 4; ++j)
            cols[i + j] = (VD)_mm512_insertf64x4(_mm512_castpd256_pd512(lo[j]), hi[j], 1);
#else
        VD block[LW];
#pragma GCC unroll 8
        for (j = 0; j < LW; ++j)
            memcpy(&block[j], rows[j] + i, sizeof block[j]);
        LNAME(transpose_block)(block, cols + i);
#endif
    }
#pragma GCC unroll 8
    for (; i < NY; ++i)
#pragma GCC unroll 8
        for (j = 0; j < LW; ++j)
            cols[i][j] = rows[j][i];
}

/* The segment's values of the lanes ls in cache, written again for those whose run has started a segment since
 * (or that were not there); the flags of the cache recomputed if any was. Out of line: rarely called. */
static __attribute__((noinline, target(LTARGET))) void LNAME(refresh)(lane *const *ls, lanes_cache *cache)
{
    VD *v = (VD *)cache->data;
    const int64_t set = -1;
    double mask; /* every bit set */
    int i, j;
    memcpy(&mask, &set, sizeof mask);
    for (j = 0; j < LW; ++j) {
        const lane *l = ls[j];
        int sine, contact;
        if (cache->who[j] == l && cache->segment[j] == l->segment)
            continue;
        cache->who[j] = l;
        cache->segment[j] = l->segment;
        for (i = 0; i < NY; ++i)
            v[LC_ATOL + i][j] = l->tol->atol[i];
        v[LC_RTOL][j] = l->tol->rtol;
#define GATHER(i) v[LC_CST + i][j] = l->o->cst[i];
        LANES_CST_USED(GATHER)
#undef GATHER
        contact = l->o->rhs == ODE_PULSE_CONTACT || l->o->rhs == ODE_FREE_CONTACT;
        sine = l->o->pulse_on && l->o->c->motion == ROCKING_MOTION_SINE;
        v[LC_CONTACT][j] = contact ? mask : 0.0;
        v[LC_SINE][j] = sine ? mask : 0.0;
        v[LC_A][j] = sine ? l->o->c->a_g : 0.0;
        v[LC_OMEGA][j] = sine ? l->o->c->omega_g : 0.0;
        v[LC_PSI][j] = sine ? l->o->c->psi : 0.0;
        cache->other[j] = l->o->pulse_on && !sine;
    }
    cache->any_contact = cache->any_rocking = cache->any_sine = cache->any_other = 0;
    for (j = 0; j < LW; ++j) {
        const int contact = ((VL)v[LC_CONTACT])[j] != 0;
        cache->any_contact |= contact;
        cache->any_rocking |= !contact;
        cache->any_sine |= ((VL)v[LC_SINE])[j] != 0;
        cache->any_other |= cache->other[j];
    }
}

/* The stages and the error estimate of the steps the LG LW lanes ls ask for (lanes_stages), dopri_stages_of and
 * dopri_error over vectors, group g of LW lanes from ls[LW g]: the stages into each lane's d->k, the new state
 * into its y_new, the error into its err; except the lanes where an argument of sin or cos was out of the vector
 * functions' range: their bits in the mask returned, the caller computes those steps scalar. caches[g]: the
 * segments' values of group g's lanes (refreshed here where they changed). The groups go side by side, stage by
 * stage: each stage's chain of operations (its point, sin and cos, the accelerations' division) waits on the
 * previous stage's, and the other groups' fill the wait. */
static __attribute__((target(LTARGET))) int LNAME(stages)(lane *const *ls, lanes_cache *caches)
{
    VD k[LG][STAGES][NY], y[LG][NY], y0[LG][NY], ag_new[LG], t0[LG], h[LG], t_new[LG];
    VL inside[LG]; /* the lanes whose arguments of sin and cos were all in range */
    const VL *lm = LNAME(mask_table)();
    int any_sine[LG], any_other[LG], any_rocking[LG], any_contact[LG]; /* the caches' flags, read once */
    int g, i, j, s, scalar = 0;
#pragma GCC unroll 4
    for (g = 0; g < LG; ++g) {
        lane *const *gl = ls + LW * g;
        lanes_cache *cache = caches + g;
        int stale = 0;
#pragma GCC unroll 8
        for (j = 0; j < LW; ++j)
            stale |= cache->who[j] != gl[j] || cache->segment[j] != gl[j]->segment;
        if (stale)
            LNAME(refresh)(gl, cache);
        any_sine[g] = cache->any_sine;
        any_other[g] = cache->any_other;
        any_rocking[g] = cache->any_rocking;
        any_contact[g] = cache->any_contact;
        const double *y_rows[LW], *f_rows[LW];
#define T0(j) gl[j]->d->t
#define H(j) gl[j]->h
#define T_NEW(j) gl[j]->t_new
        t0[g] = LGATHER(T0);
        h[g] = LGATHER(H);
        t_new[g] = LGATHER(T_NEW);
#undef T0
#undef H
#undef T_NEW
#pragma GCC unroll 8
        for (j = 0; j < LW; ++j) {
            y_rows[j] = gl[j]->d->y;
            f_rows[j] = gl[j]->d->f;
        }
        LNAME(load_rows)(y_rows, y0[g]);
        LNAME(load_rows)(f_rows, k[g][0]);
        ag_new[g] = LNAME(splat)(0.0);
        inside[g] = (VL){0} - 1;
    }
    /* A loop, not unrolled: the kernel's code is then less than half as long (SSE2: 19 kB, 8 kB), the CPU fetches
     * it faster and it leaves more of the instruction cache to the lanes' scalar code (bench map, SSE2: about 1 %
     * less CPU time; AVX2 the same or less). */
#pragma GCC unroll 1
    for (s = 1; s < STAGES; ++s) {
#pragma GCC unroll 4
        for (g = 0; g < LG; ++g) {
            const VD *v = (const VD *)caches[g].data, *cst = v + LC_CST; /* after the refresh */
            lane *const *gl = ls + LW * g;
            const int *other = caches[g].other;
            VD acc[NY], ag;
#pragma GCC unroll 8
            for (i = 0; i < NY; ++i) {
                acc[i] = RK_A[s][0] * k[g][0][i];
#pragma GCC unroll 8
                for (j = 1; j < s; ++j)
                    acc[i] += RK_A[s][j] * k[g][j][i];
                y[g][i] = y0[g][i] + h[g] * acc[i];
            }
            if (RK_C[s] == 1.0) { /* the last stages sit at t_new: one ground acceleration there (ode_ag's memo) */
                if (RK_C[s - 1] != 1.0)
                    ag_new[g] = LNAME(ground)(gl, t_new[g], other, any_sine[g], any_other[g], v, &inside[g]);
                ag = ag_new[g];
            } else {
                ag = LNAME(ground)(gl, t0[g] + RK_C[s] * h[g], other, any_sine[g], any_other[g], v, &inside[g]);
            }
            if (any_rocking[g]) {
                LNAME(rocking_accel)(y[g], ag, cst, k[g][s] + NQ, &inside[g]);
            } else {
#pragma GCC unroll 8
                for (i = 0; i < NQ; ++i)
                    k[g][s][NQ + i] = LNAME(splat)(0.0);
            }
#if LANES_CONTACT
            if (any_contact[g]) {
                const VL contact = (VL)v[LC_CONTACT];
                VD in_contact[NQ];
                LNAME(contact_accel)(y[g], ag, cst, in_contact, &inside[g]);
#pragma GCC unroll 8
                for (i = 0; i < NQ; ++i)
                    k[g][s][NQ + i] = (VD)((contact & (VL)in_contact[i]) | (~contact & (VL)k[g][s][NQ + i]));
            }
#endif
#pragma GCC unroll 8
            for (i = 0; i < NQ; ++i)
                k[g][s][i] = y[g][NQ + i];
        }
    }
#pragma GCC unroll 4
    for (g = 0; g < LG; ++g)
#pragma GCC unroll 8
        for (j = 0; j < LW; ++j)
            scalar |= inside[g][j] == 0 ? 1 << (LW * g + j) : 0;
    VD err[LG], power[LG];
    VL normal[LG];
#pragma GCC unroll 4
    for (g = 0; g < LG; ++g) {
        const VD *v = (const VD *)caches[g].data;
        VD sum = LNAME(splat)(0.0);
#pragma GCC unroll 8
        for (i = 0; i < NY; ++i) {
            const VD a = (VD)((VL)y0[g][i] & LM(MAGNITUDE)), b = (VD)((VL)y[g][i] & LM(MAGNITUDE));
            VD e = RK_E[0] * k[g][0][i], r;
#pragma GCC unroll 8
            for (s = 1; s < STAGES; ++s)
                e += RK_E[s] * k[g][s][i];
            e *= h[g];
            r = e / (v[LC_ATOL + i] + v[LC_RTOL] * LNAME(max)(a, b));
            sum += r * r;
        }
        normal[g] = (VL){0} - 1;
        err[g] = LNAME(sqrt)(sum / NY);
        power[g] = LNAME(error_power)(err[g], &normal[g]);
    }
    if (scalar == 0) { /* each lane's stages and new state at once (else lane by lane: those of the others) */
#pragma GCC unroll 4
        for (g = 0; g < LG; ++g) {
            lane *const *gl = ls + LW * g;
            double *rows[LW], *stages[LW]; /* the lanes' d->k, rows of NA doubles */
#pragma GCC unroll 8
            for (j = 0; j < LW; ++j) {
                rows[j] = gl[j]->y_new;
                stages[j] = gl[j]->d->k[0];
            }
            LNAME(store_rows)(y[g], rows);
#pragma GCC unroll 8
            for (s = 0; s < STAGES; ++s) {
#pragma GCC unroll 8
                for (j = 0; j < LW; ++j)
                    rows[j] = stages[j] + s * NA;
                LNAME(store_rows)(k[g][s], rows);
            }
        }
    }
#pragma GCC unroll 4
    for (g = 0; g < LG; ++g) {
        const VD *v = (const VD *)caches[g].data;
#pragma GCC unroll 8
        for (j = 0; j < LW; ++j) {
            lane *l = ls[LW * g + j];
            if (scalar & (1 << (LW * g + j)))
                continue;
            l->err = err[g][j];
            l->power = normal[g][j] ? power[g][j] : pow(err[g][j], ERROR_EXPONENT);
            if (scalar != 0) {
                for (s = 0; s < STAGES; ++s)
                    for (i = 0; i < NY; ++i)
                        l->d->k[s][i] = k[g][s][i][j];
                for (i = 0; i < NY; ++i)
                    l->y_new[i] = y[g][i][j];
            }
            if (((VL)v[LC_SINE])[j]) { /* ode_ag's memo, as the scalar stages leave it */
                l->o->memo_t = t_new[g][j];
                l->o->memo_ag = ag_new[g][j];
            }
        }
    }
    return scalar;
}

#undef LGATHER
#undef LSPLAT
#undef LK
#undef LM
#undef LBLOCK
#undef LATTR
#undef VD
#undef VL
