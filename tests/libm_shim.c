/* Another libm for the simulator: loaded with LD_PRELOAD by `make check-portable`.
 *
 * Half of the results of sin, cos, tan, atan, exp, expm1, log, log1p, pow and atan2 called
 * from the simulator's own libraries (not from Python, NumPy or SciPy) move one unit in the
 * last place towards zero: a faithful libm may round either way, and which way depends on the
 * CPU (NumPy's SIMD functions against C's libm). A test that holds only bit for bit between
 * the two fails under this shim. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

/* The caller is the simulator: a library outside Python, its packages and the C library. */
static int from_simulator(void *caller)
{
    Dl_info info;
    if (!dladdr(caller, &info) || !info.dli_fname)
        return 0;
    return !strstr(info.dli_fname, "python") && !strstr(info.dli_fname, "site-packages") &&
           !strstr(info.dli_fname, "libm.") && !strstr(info.dli_fname, "libc.");
}

/* One unit towards zero for the arguments whose bit 3 is set: half of them, reproducibly. */
static double moved(double x, double r)
{
    uint64_t bits;
    memcpy(&bits, &x, sizeof bits);
    if (!isfinite(r) || r == 0.0 || !((bits >> 3) & 1))
        return r;
    return nextafter(r, 0.0);
}

#define ONE(f)                                                                               \
    double f(double x)                                                                       \
    {                                                                                        \
        static double (*real)(double);                                                       \
        if (!real)                                                                           \
            real = (double (*)(double))dlsym(RTLD_NEXT, #f);                                 \
        double r = real(x);                                                                  \
        return from_simulator(__builtin_return_address(0)) ? moved(x, r) : r;                \
    }
#define TWO(f)                                                                               \
    double f(double x, double y)                                                             \
    {                                                                                        \
        static double (*real)(double, double);                                               \
        if (!real)                                                                           \
            real = (double (*)(double, double))dlsym(RTLD_NEXT, #f);                         \
        double r = real(x, y);                                                               \
        return from_simulator(__builtin_return_address(0)) ? moved(x + y, r) : r;            \
    }

ONE(sin) ONE(cos) ONE(tan) ONE(atan) ONE(exp) ONE(expm1) ONE(log) ONE(log1p)
TWO(pow) TWO(atan2)
