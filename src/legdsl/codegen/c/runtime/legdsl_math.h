/* legdsl_math.h: the arithmetic helpers of the generated C (legdsl's C backend).
 *
 * Each helper computes what C computes (libm's function, IEEE division) and, where Python's
 * float arithmetic or math module would raise instead, records the error in *err: the first
 * error of a call wins, as the first exception does in Python. The run loop checks *err where
 * Python would have stopped, so a run that fails stops at the same step with the same message.
 * A name `err` (int *) must be in scope where these are used.
 */
#ifndef LEGDSL_MATH_H
#define LEGDSL_MATH_H

#include <math.h>
#include <stdint.h>
#include <string.h>

enum {
    LEG_OK = 0,
    LEG_EDOM = 1,       /* ValueError: math domain error */
    LEG_EZERODIV = 2,   /* ZeroDivisionError: float division by zero */
    LEG_ERANGE = 3,     /* OverflowError: math range error */
    LEG_EPOWZERO = 4,   /* ZeroDivisionError: 0.0 cannot be raised to a negative power */
    LEG_EPOWRANGE = 5,  /* OverflowError: (34, 'Numerical result out of range') */
    LEG_ECOMPLEX = 6    /* a negative number to a fractional power (complex in Python) */
};

static inline void leg_flag(int *err, int code) {
    if (*err == LEG_OK) *err = code;
}

/* Python's a / b: ZeroDivisionError when b is zero (either sign). */
static inline double leg_div_e(double a, double b, int *err) {
    if (b == 0.0) leg_flag(err, LEG_EZERODIV);
    return a / b;
}

/* CPython's math_1: a NaN from a non-NaN argument is a domain error. */
static inline double leg_math1(double r, double x, int *err) {
    if (isnan(r) && !isnan(x)) leg_flag(err, LEG_EDOM);
    else if (isinf(r) && isfinite(x)) leg_flag(err, LEG_EDOM);
    return r;
}

static inline double leg_sin_e(double x, int *err) { return leg_math1(sin(x), x, err); }
static inline double leg_cos_e(double x, int *err) { return leg_math1(cos(x), x, err); }

/* sin and cos, remembered (the generated dynamics.c): the kinematic functions of one state
 * (forward dynamics, the contacts' positions, velocities and Jacobians, the body poses...) each
 * take the sine and cosine of the same joint angles, and libm's sincos was a quarter of a step.
 * A small table per thread (leg_trig_table, step.c; each generated function asks for it once),
 * indexed by the argument's bits and checked against them in full, gives back libm's own two
 * values for an argument seen before: the same doubles as calling libm again (-0.0 and 0.0
 * are different keys; a NaN goes to libm and is never stored). */
#define LEG_TRIG_BITS 6
typedef struct { uint64_t key; double s, c; } leg_trig_entry;
leg_trig_entry *leg_trig_table(void);

#if defined(__GLIBC__) /* glibc's sincos: the same two doubles as its sin and cos, in one call */
void sincos(double x, double *s, double *c);
#define LEG_SINCOS(x, s, c) sincos((x), (s), (c))
#else
#define LEG_SINCOS(x, s, c) (*(s) = sin(x), *(c) = cos(x))
#endif

static __attribute__((noinline)) void leg_trig_fill(leg_trig_entry *e, uint64_t key, double x) {
    LEG_SINCOS(x, &e->s, &e->c);
    e->key = key;
}
static inline __attribute__((always_inline)) const leg_trig_entry *leg_trig_find(
    leg_trig_entry *table, double x) {
    uint64_t bits;
    memcpy(&bits, &x, sizeof bits);
    uint64_t key = bits + 1; /* 0, an empty slot, would be the NaN with every bit set */
    leg_trig_entry *e = table + (((bits ^ (bits >> 31)) * 0x9E3779B97F4A7C15ull) >>
                                 (64 - LEG_TRIG_BITS));
    if (e->key != key) leg_trig_fill(e, key, x);
    return e;
}
static inline __attribute__((always_inline)) double leg_sin_t(double x, leg_trig_entry *table,
                                                              int *err) {
    return leg_math1(isnan(x) ? sin(x) : leg_trig_find(table, x)->s, x, err);
}
static inline __attribute__((always_inline)) double leg_cos_t(double x, leg_trig_entry *table,
                                                              int *err) {
    return leg_math1(isnan(x) ? cos(x) : leg_trig_find(table, x)->c, x, err);
}
#define LEG_PI 3.141592653589793 /* Python's math.pi (M_PI is not ISO C) */
static inline double leg_tan_e(double x, int *err) { return leg_math1(tan(x), x, err); }
static inline double leg_asin_e(double x, int *err) { return leg_math1(asin(x), x, err); }
static inline double leg_acos_e(double x, int *err) { return leg_math1(acos(x), x, err); }

/* math.exp: an overflow from a finite argument is a range error (math_1 with can_overflow) */
static inline double leg_exp_e(double x, int *err) {
    double r = exp(x);
    if (isinf(r) && isfinite(x)) leg_flag(err, LEG_ERANGE);
    return r;
}

/* math.sqrt: a domain error below zero (CPython's math_1 again). */
static inline double leg_sqrt_e(double x, int *err) { return leg_math1(sqrt(x), x, err); }

/* math.log (CPython's loghelper/m_log): zero and negative numbers are domain errors. */
static inline double leg_log_e(double x, int *err) {
    if (isfinite(x) && x <= 0.0) {
        leg_flag(err, LEG_EDOM);
        return NAN;
    }
    if (isnan(x) || x == INFINITY) return x;
    if (x == -INFINITY) {
        leg_flag(err, LEG_EDOM);
        return NAN;
    }
    return log(x);
}

/* CPython's float_pow for the cases the generated code can meet. */
static inline double leg_pow_e(double x, double y, int *err) {
    if (y == 0.0) return 1.0;
    if (isnan(x)) return x;
    if (isnan(y)) return x == 1.0 ? 1.0 : y;
    if (x == 0.0 && y < 0.0 && isfinite(y)) {
        leg_flag(err, LEG_EPOWZERO);
        return NAN;
    }
    if (x < 0.0 && isfinite(x) && isfinite(y) && floor(y) != y) {
        leg_flag(err, LEG_ECOMPLEX);
        return NAN;
    }
    double r = pow(x, y);
    if (isinf(r) && isfinite(x) && isfinite(y) && x != 0.0) leg_flag(err, LEG_EPOWRANGE);
    return r;
}

/* The generated Python's maximum(a, b) and minimum(a, b): NaN when either is NaN (unlike fmax
 * and fmin, which drop it), else the first argument unless the second compares greater
 * (smaller), as Python's max and min. */
static inline double leg_max(double a, double b) {
    return a != a || b != b ? NAN : b > a ? b : a;
}
static inline double leg_min(double a, double b) {
    return a != a || b != b ? NAN : b < a ? b : a;
}
/* A planar creature's pitch past 90 deg, over the whole turn, from its rotation's row-major
 * entries (sensors.rpy): the 3D reading folds back there. */
static inline double leg_whole_turn_pitch(const double *rot, int *err) {
    double s = leg_max(-1.0, leg_min(1.0, -rot[6]));
    return copysign(LEG_PI, s) - leg_asin_e(s, err);
}

#define leg_div(a, b) leg_div_e((a), (b), err)
#ifdef LEG_TRIG_LOCAL /* a function that declared leg_trig_here = leg_trig_table() */
#define leg_sin(x) leg_sin_t((x), leg_trig_here, err)
#define leg_cos(x) leg_cos_t((x), leg_trig_here, err)
#else
#define leg_sin(x) leg_sin_e((x), err)
#define leg_cos(x) leg_cos_e((x), err)
#endif
#define leg_tan(x) leg_tan_e((x), err)
#define leg_asin(x) leg_asin_e((x), err)
#define leg_acos(x) leg_acos_e((x), err)
#define leg_sqrt(x) leg_sqrt_e((x), err)
#define leg_log(x) leg_log_e((x), err)
#define leg_exp(x) leg_exp_e((x), err)
#define leg_pow(x, y) leg_pow_e((x), (y), err)

#endif
