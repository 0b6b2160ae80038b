/*
 * tru_math.h -- small helpers for 3-vectors, 3x3 matrices (row-major) and tiny
 * dense solves.  They take no model or data; the result comes first.
 */
#ifndef TRU_MATH_H
#define TRU_MATH_H

#include <math.h>

static inline void tru_cross3(double res[3], const double a[3], const double b[3])
{
    const double r0 = a[1] * b[2] - a[2] * b[1];
    const double r1 = a[2] * b[0] - a[0] * b[2];
    const double r2 = a[0] * b[1] - a[1] * b[0];
    res[0] = r0;
    res[1] = r1;
    res[2] = r2;
}

static inline double tru_dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static inline double tru_norm3(const double a[3])
{
    return sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
}

/* res = M x */
static inline void tru_matvec3(double res[3], const double M[9], const double x[3])
{
    const double r0 = M[0] * x[0] + M[1] * x[1] + M[2] * x[2];
    const double r1 = M[3] * x[0] + M[4] * x[1] + M[5] * x[2];
    const double r2 = M[6] * x[0] + M[7] * x[1] + M[8] * x[2];
    res[0] = r0;
    res[1] = r1;
    res[2] = r2;
}

/* res = M^T x */
static inline void tru_mattvec3(double res[3], const double M[9], const double x[3])
{
    const double r0 = M[0] * x[0] + M[3] * x[1] + M[6] * x[2];
    const double r1 = M[1] * x[0] + M[4] * x[1] + M[7] * x[2];
    const double r2 = M[2] * x[0] + M[5] * x[1] + M[8] * x[2];
    res[0] = r0;
    res[1] = r1;
    res[2] = r2;
}

/* res = A B (res may not alias A or B) */
static inline void tru_matmul3(double res[9], const double A[9], const double B[9])
{
    int i, j;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++)
            res[3 * i + j] = A[3 * i] * B[j] + A[3 * i + 1] * B[3 + j] + A[3 * i + 2] * B[6 + j];
}

/* skew matrix: S x = a x x */
static inline void tru_skew3(double S[9], const double a[3])
{
    S[0] = 0.0;
    S[1] = -a[2];
    S[2] = a[1];
    S[3] = a[2];
    S[4] = 0.0;
    S[5] = -a[0];
    S[6] = -a[1];
    S[7] = a[0];
    S[8] = 0.0;
}

/* Max-norm of v (n); NaN propagates. */
static inline double tru_maxnorm(const double *v, int n)
{
    double r = 0.0;
    int i;
    for (i = 0; i < n; i++) {
        const double a = fabs(v[i]);
        if (!(a <= r)) r = a;
    }
    return r;
}

/* Sum of squares of v (n). */
static inline double tru_sumsq(const double *v, int n)
{
    double r = 0.0;
    int i;
    for (i = 0; i < n; i++) r += v[i] * v[i];
    return r;
}

/* Solve A x = b in place (A n x n row-major, destroyed; b overwritten by x) by
 * Gaussian elimination with partial pivoting.  Returns 0, or -1 if singular. */
static inline int tru_solve_dense(int n, double *A, double *b)
{
    int i, j, c;
    for (c = 0; c < n; c++) {
        int piv = c;
        double amax = fabs(A[c * n + c]);
        for (i = c + 1; i < n; i++) {
            const double ai = fabs(A[i * n + c]);
            if (ai > amax) {
                amax = ai;
                piv = i;
            }
        }
        if (!(amax > 0.0)) return -1;
        if (piv != c) {
            for (j = c; j < n; j++) {
                const double tmp = A[c * n + j];
                A[c * n + j] = A[piv * n + j];
                A[piv * n + j] = tmp;
            }
            {
                const double tmp = b[c];
                b[c] = b[piv];
                b[piv] = tmp;
            }
        }
        for (i = c + 1; i < n; i++) {
            const double l = A[i * n + c] / A[c * n + c];
            if (l != 0.0) {
                for (j = c + 1; j < n; j++) A[i * n + j] -= l * A[c * n + j];
                b[i] -= l * b[c];
            }
        }
    }
    for (i = n - 1; i >= 0; i--) {
        double sum = b[i];
        for (j = i + 1; j < n; j++) sum -= A[i * n + j] * b[j];
        b[i] = sum / A[i * n + i];
    }
    return 0;
}

/* P A = L U in place by Gaussian elimination with partial pivoting (A n x n, row-major,
 * leading dimension lda; L unit lower below the diagonal, U on and above): row c was
 * swapped with row piv[c] >= c at step c.  *sign: the sign of det A (0 if a pivot
 * column is zero: the column is then left as it is, U has a zero on its diagonal).
 * Never fails and allocates nothing; whether U is usable is the caller's to judge. */
static inline void tru_lu_factor(int n, double *A, int lda, int *piv, int *sign)
{
    int i, j, c, sg = 1;
    for (c = 0; c < n; c++) {
        double *rc = A + (size_t)c * lda, amax = fabs(rc[c]);
        int p = c;
        for (i = c + 1; i < n; i++) {
            const double ai = fabs(A[(size_t)i * lda + c]);
            if (ai > amax) amax = ai, p = i;
        }
        piv[c] = p;
        if (p != c) {
            double *rp = A + (size_t)p * lda;
            for (j = 0; j < n; j++) {
                const double t = rc[j];
                rc[j] = rp[j], rp[j] = t;
            }
            sg = -sg;
        }
        if (!(amax > 0.0)) {
            if (!(amax == amax)) continue; /* NaN: left for the caller's check */
            sg = 0;
            continue;
        }
        if (rc[c] < 0.0) sg = -sg;
        for (i = c + 1; i < n; i++) {
            double *ri = A + (size_t)i * lda;
            const double l = ri[c] / rc[c];
            ri[c] = l;
            if (l != 0.0)
                for (j = c + 1; j < n; j++) ri[j] -= l * rc[j];
        }
    }
    *sign = sg;
}

/* A x = b from tru_lu_factor's factors, b overwritten by x. */
static inline void tru_lu_solve(int n, const double *LU, int lda, const int *piv, double *b)
{
    int i, j;
    for (i = 0; i < n; i++)
        if (piv[i] != i) {
            const double t = b[i];
            b[i] = b[piv[i]], b[piv[i]] = t;
        }
    for (i = 1; i < n; i++) {
        const double *ri = LU + (size_t)i * lda;
        double s = b[i];
        for (j = 0; j < i; j++) s -= ri[j] * b[j];
        b[i] = s;
    }
    for (i = n - 1; i >= 0; i--) {
        const double *ri = LU + (size_t)i * lda;
        double s = b[i];
        for (j = i + 1; j < n; j++) s -= ri[j] * b[j];
        b[i] = s / ri[i];
    }
}

/* A^T x = b from tru_lu_factor's factors (A^T = U^T L^T P), b overwritten by x. */
static inline void tru_lu_solve_trans(int n, const double *LU, int lda, const int *piv, double *b)
{
    int i, j;
    for (j = 0; j < n; j++) { /* U^T z = b: column j of U, forward */
        const double bj = b[j] / LU[(size_t)j * lda + j];
        b[j] = bj;
        for (i = j + 1; i < n; i++) b[i] -= LU[(size_t)j * lda + i] * bj;
    }
    for (j = n - 1; j >= 0; j--) { /* L^T y = z: unit, backward */
        const double bj = b[j];
        for (i = 0; i < j; i++) b[i] -= LU[(size_t)j * lda + i] * bj;
    }
    for (i = n - 1; i >= 0; i--)
        if (piv[i] != i) {
            const double t = b[i];
            b[i] = b[piv[i]], b[piv[i]] = t;
        }
}

#endif /* TRU_MATH_H */
