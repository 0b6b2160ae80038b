/*
 * tr_hd.h -- hyper-dual numbers: exact first and second derivatives of a function of a
 * few variables without finite-difference noise.
 *
 * x = v + a e1 + b e2 + c e1 e2 with e1^2 = e2^2 = 0: evaluating f at x0 + e1 d1 + e2 d2
 * gives f(x0) in v, the directional derivatives along d1 and d2 in a and b, and the
 * second derivative d1^T (d^2 f) d2 in c, each exact to round-off.  A smooth function g
 * maps x to (g(v), g'(v) a, g'(v) b, g'(v) c + g''(v) a b).
 */
#ifndef TR_HD_H
#define TR_HD_H

#include <math.h>

typedef struct {
    double v, a, b, c;
} tr_hd;

static inline tr_hd hd_c(double v)
{
    tr_hd r = {v, 0.0, 0.0, 0.0};
    return r;
}

static inline tr_hd hd_add(tr_hd x, tr_hd y)
{
    tr_hd r = {x.v + y.v, x.a + y.a, x.b + y.b, x.c + y.c};
    return r;
}

static inline tr_hd hd_sub(tr_hd x, tr_hd y)
{
    tr_hd r = {x.v - y.v, x.a - y.a, x.b - y.b, x.c - y.c};
    return r;
}

static inline tr_hd hd_scale(tr_hd x, double s)
{
    tr_hd r = {x.v * s, x.a * s, x.b * s, x.c * s};
    return r;
}

static inline tr_hd hd_mul(tr_hd x, tr_hd y)
{
    tr_hd r = {x.v * y.v, x.v * y.a + x.a * y.v, x.v * y.b + x.b * y.v,
               x.v * y.c + x.a * y.b + x.b * y.a + x.c * y.v};
    return r;
}

/* g(x) from g(v), g'(v), g''(v) */
static inline tr_hd hd_fn(tr_hd x, double g, double g1, double g2)
{
    tr_hd r = {g, g1 * x.a, g1 * x.b, g1 * x.c + g2 * x.a * x.b};
    return r;
}

static inline tr_hd hd_inv(tr_hd x)
{
    const double i = 1.0 / x.v;
    return hd_fn(x, i, -i * i, 2.0 * i * i * i);
}

static inline tr_hd hd_div(tr_hd x, tr_hd y)
{
    return hd_mul(x, hd_inv(y));
}

/* sqrt(x), x > 0 */
static inline tr_hd hd_sqrt(tr_hd x)
{
    const double s = sqrt(x.v);
    return hd_fn(x, s, 0.5 / s, -0.25 / (s * x.v));
}

/* atan2(y, x), (x, y) != 0 */
static inline tr_hd hd_atan2(tr_hd y, tr_hd x)
{
    const double r2 = x.v * x.v + y.v * y.v, r4 = r2 * r2;
    const double tx = -y.v / r2, ty = x.v / r2;
    const double txx = 2.0 * x.v * y.v / r4, tyy = -txx, txy = (y.v * y.v - x.v * x.v) / r4;
    tr_hd r;
    r.v = atan2(y.v, x.v);
    r.a = tx * x.a + ty * y.a;
    r.b = tx * x.b + ty * y.b;
    r.c = tx * x.c + ty * y.c + txx * x.a * x.b + txy * (x.a * y.b + y.a * x.b) + tyy * y.a * y.b;
    return r;
}

/* a x + b y + c z */
static inline tr_hd hd_lin3(const tr_hd *x, double a, const tr_hd *y, double b, const tr_hd *z,
                            double c)
{
    return hd_add(hd_add(hd_scale(*x, a), hd_scale(*y, b)), hd_scale(*z, c));
}

/* r = A x, x constant */
static inline void hd_matvec3c(tr_hd *r, const tr_hd *A, const double *x)
{
    int i;
    for (i = 0; i < 3; i++)
        r[i] = hd_lin3(A + 3 * i, x[0], A + 3 * i + 1, x[1], A + 3 * i + 2, x[2]);
}

static inline tr_hd hd_dot3(const tr_hd *x, const tr_hd *y)
{
    return hd_add(hd_add(hd_mul(x[0], y[0]), hd_mul(x[1], y[1])), hd_mul(x[2], y[2]));
}

/* r = A B, 3 x 3 row-major */
static inline void hd_matmul3(tr_hd *r, const tr_hd *A, const tr_hd *B)
{
    int i, j;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++)
            r[3 * i + j] = hd_add(hd_add(hd_mul(A[3 * i], B[j]), hd_mul(A[3 * i + 1], B[3 + j])),
                                  hd_mul(A[3 * i + 2], B[6 + j]));
}

/* r = A x */
static inline void hd_matvec3(tr_hd *r, const tr_hd *A, const tr_hd *x)
{
    int i;
    for (i = 0; i < 3; i++)
        r[i] = hd_add(hd_add(hd_mul(A[3 * i], x[0]), hd_mul(A[3 * i + 1], x[1])),
                      hd_mul(A[3 * i + 2], x[2]));
}

/* r = a x b */
static inline void hd_cross3(tr_hd *r, const tr_hd *a, const tr_hd *b)
{
    r[0] = hd_sub(hd_mul(a[1], b[2]), hd_mul(a[2], b[1]));
    r[1] = hd_sub(hd_mul(a[2], b[0]), hd_mul(a[0], b[2]));
    r[2] = hd_sub(hd_mul(a[0], b[1]), hd_mul(a[1], b[0]));
}

#endif /* TR_HD_H */
