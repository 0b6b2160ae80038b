/*
 * tr_qp.c -- the small dense convex QP of tr_qp.h by the primal active-set method: the
 * null space of the working set's constraints and the least-squares multipliers by SVD
 * (one-sided Jacobi), the reduced Newton system by Gaussian elimination (tru_solve_dense).
 */
#include "tr_qp.h"

#include <float.h>
#include <math.h>
#include <string.h>

#include <gsl/gsl_linalg.h>

#include "tendonrod.h"
#include "tru_math.h"

typedef struct {
    int n, me, mi, rows; /* rows: me + mi, the most a working set's matrix holds */
    double *x, *q, *p, *Gx, *h, *rowmax, *Gp, *y, *tmp;
    double *C;     /* (rows x n) the working set's constraint rows */
    double *P, *V; /* SVD: (big x big) the padded matrix (then U), (big x big) V */
    double *S;     /* (big) singular values */
    double *Z;     /* (n x n) null-space basis, column-major by basis vector: Z[j * n + i] */
    double *M;     /* (n x n) the reduced Hessian Z^T H Z, then its elimination */
    double *L;     /* tr_lstsq's workspace for the working set's rows */
} qp_ws;

size_t tr_qp_work_len(int n, int me, int mi)
{
    const size_t rows = (size_t)me + (size_t)mi, big = (rows > (size_t)n ? rows : (size_t)n);
    return 6 * (size_t)n + 4 * (size_t)mi + 2 * rows + rows * (size_t)n + 2 * big * big + big +
           2 * (size_t)n * (size_t)n + big + tr_lstsq_work_len((int)big, (int)big);
}

static void ws_init(qp_ws *w, int n, int me, int mi, double *work)
{
    const size_t rows = (size_t)me + (size_t)mi, big = (rows > (size_t)n ? rows : (size_t)n);
    w->n = n, w->me = me, w->mi = mi, w->rows = (int)rows;
    w->x = work, work += n;
    w->q = work, work += n;
    w->p = work, work += n;
    w->tmp = work, work += 3 * (size_t)n + big;
    w->Gx = work, work += mi;
    w->h = work, work += mi;
    w->rowmax = work, work += mi;
    w->Gp = work, work += mi;
    w->y = work, work += 2 * rows;
    w->C = work, work += rows * (size_t)n;
    w->P = work, work += big * big;
    w->V = work, work += big * big;
    w->S = work, work += big;
    w->Z = work, work += (size_t)n * n;
    w->M = work, work += (size_t)n * n;
    w->L = work;
}

/* Singular value decomposition of the (r x c) row-major matrix a, r >= c: U into w->P
 * (r x c), V into w->V (c x c), singular values into w->S (c). */
static int svd(qp_ws *w, const double *a, int r, int c)
{
    gsl_matrix_view P = gsl_matrix_view_array(w->P, (size_t)r, (size_t)c);
    gsl_matrix_view V = gsl_matrix_view_array(w->V, (size_t)c, (size_t)c);
    gsl_vector_view S = gsl_vector_view_array(w->S, (size_t)c);
    memcpy(w->P, a, (size_t)r * (size_t)c * sizeof(double));
    return gsl_linalg_SV_decomp_jacobi(&P.matrix, &V.matrix, &S.vector) == GSL_SUCCESS ? 0 : -1;
}

/* The k rows of C padded with zero rows to at least n, decomposed: the number of rows. */
static int svd_rows(qp_ws *w, int k)
{
    const int n = w->n, r = k > n ? k : n;
    double *a = w->M; /* scratch (n x n: r = n here) */
    if (r == k) return svd(w, w->C, k, n) == 0 ? r : -1;
    memcpy(a, w->C, (size_t)k * (size_t)n * sizeof(double));
    memset(a + (size_t)k * n, 0, (size_t)(r - k) * (size_t)n * sizeof(double));
    return svd(w, a, r, n) == 0 ? r : -1;
}

/* An orthonormal basis of the null space of the k rows of C into w->Z: its dimension. */
static int null_space(qp_ws *w, int k)
{
    const int n = w->n;
    double smax = 0.0, thr;
    int i, j, nz = 0;
    if (k == 0) {
        memset(w->Z, 0, (size_t)n * n * sizeof(double));
        for (i = 0; i < n; i++) w->Z[i * n + i] = 1.0;
        return n;
    }
    if (svd_rows(w, k) < 0) return -1;
    for (j = 0; j < n; j++)
        if (w->S[j] > smax) smax = w->S[j];
    thr = 1e-12 * (smax > 1e-300 ? smax : 1e-300);
    for (j = 0; j < n; j++) {
        if (w->S[j] > thr) continue;
        for (i = 0; i < n; i++) w->Z[nz * n + i] = w->V[i * n + j];
        nz++;
    }
    return nz;
}

/* q = H x + g. */
static void gradient(const qp_ws *w, const double *H, const double *g, const double *x, double *q)
{
    const int n = w->n;
    int i, j;
    for (i = 0; i < n; i++) {
        double s = g[i];
        for (j = 0; j < n; j++) s += H[i * n + j] * x[j];
        q[i] = s;
    }
}

/* The step p = -Z (Z^T H Z)^-1 Z^T q within the null space of the k rows of C (0 when it
 * is empty); -1 for a singular reduced Hessian or a failed SVD. */
static int reduced_step(qp_ws *w, const double *H, int k, double *p)
{
    const int n = w->n;
    double *HZ = w->tmp, *rhs = w->tmp + n;
    int nz, a, b, i, j;
    nz = null_space(w, k);
    if (nz < 0) return -1;
    memset(p, 0, (size_t)n * sizeof(double));
    if (nz == 0) return 0;
    for (a = 0; a < nz; a++) {
        const double *za = w->Z + (size_t)a * n;
        for (i = 0; i < n; i++) {
            double s = 0.0;
            for (j = 0; j < n; j++) s += H[i * n + j] * za[j];
            HZ[i] = s;
        }
        for (b = 0; b < nz; b++) {
            const double *zb = w->Z + (size_t)b * n;
            double s = 0.0;
            for (i = 0; i < n; i++) s += zb[i] * HZ[i];
            w->M[b * nz + a] = s;
        }
        rhs[a] = 0.0;
        for (i = 0; i < n; i++) rhs[a] += za[i] * w->q[i];
    }
    if (tru_solve_dense(nz, w->M, rhs) < 0) return -1;
    for (a = 0; a < nz; a++)
        for (i = 0; i < n; i++) p[i] -= w->Z[(size_t)a * n + i] * rhs[a];
    return 0;
}

size_t tr_lstsq_work_len(int r, int c)
{
    const size_t big = (size_t)(r > c ? r : c), sm = (size_t)(r > c ? c : r);
    return big * sm + sm * sm + 2 * sm;
}

int tr_lstsq(int r, int c, const double *M, int trans, const double *b, double rcond, double *x,
             double *work)
{
    /* E = M (r x c), or M^T (c x r) with trans: er x ec */
    const int er = trans ? c : r, ec = trans ? r : c, tall = er >= ec;
    const int big = tall ? er : ec, sm = tall ? ec : er;
    double *P = work, *V = P + (size_t)big * sm, *S = V + (size_t)sm * sm, *tmp = S + sm;
    const double *left, *right;
    double smax = 0.0, thr;
    int i, j;
    if (sm == 0) {
        if (ec > 0) memset(x, 0, (size_t)ec * sizeof(double));
        return 0;
    }
    /* P: the taller of E and E^T (big x sm); M is E (trans = 0) or E^T (trans = 1) */
    if (tall == !trans) {
        memcpy(P, M, (size_t)big * sm * sizeof(double));
    } else {
        for (i = 0; i < big; i++)
            for (j = 0; j < sm; j++) P[(size_t)i * sm + j] = M[(size_t)j * big + i];
    }
    {
        gsl_matrix_view Pv = gsl_matrix_view_array(P, (size_t)big, (size_t)sm);
        gsl_matrix_view Vv = gsl_matrix_view_array(V, (size_t)sm, (size_t)sm);
        gsl_vector_view Sv = gsl_vector_view_array(S, (size_t)sm);
        if (gsl_linalg_SV_decomp_jacobi(&Pv.matrix, &Vv.matrix, &Sv.vector) != GSL_SUCCESS)
            return -1;
    }
    /* tall: E = P S V^T, x = V S+ P^T b; wide: E^T = P S V^T, E = V S P^T, x = P S+ V^T b.
     * The factor contracted with b (er rows) and the one that gives x (ec rows), both sm
     * columns wide. */
    left = tall ? P : V, right = tall ? V : P;
    for (j = 0; j < sm; j++)
        if (S[j] > smax) smax = S[j];
    thr = rcond * smax;
    for (j = 0; j < sm; j++) {
        double s = 0.0;
        if (S[j] > thr)
            for (i = 0; i < er; i++) s += left[(size_t)i * sm + j] * b[i];
        tmp[j] = S[j] > thr ? s / S[j] : 0.0;
    }
    for (i = 0; i < ec; i++) {
        double s = 0.0;
        for (j = 0; j < sm; j++) s += right[(size_t)i * sm + j] * tmp[j];
        x[i] = s;
    }
    return 0;
}

/* The minimum-norm least-squares solution y (k) of C^T y = r for the k rows of C, with
 * singular values below eps max(n, k) of the largest dropped (NumPy's lstsq default). */
static int lstsq_t(qp_ws *w, int k, const double *r, double *y)
{
    const int n = w->n;
    return tr_lstsq(k, n, w->C, 1, r, DBL_EPSILON * (n > k ? n : k), y, w->L);
}

/* Rows of C: A's, then G's rows in the working set ws (nw). */
static int stack_rows(qp_ws *w, const double *A, const double *G, const int *ws, int nw)
{
    const int n = w->n;
    int i;
    memcpy(w->C, A, (size_t)w->me * (size_t)n * sizeof(double));
    for (i = 0; i < nw; i++)
        memcpy(w->C + (size_t)(w->me + i) * n, G + (size_t)ws[i] * n, (size_t)n * sizeof(double));
    return w->me + nw;
}

static double maxabs(const double *v, int n)
{
    double m = 0.0;
    int i;
    for (i = 0; i < n; i++)
        if (fabs(v[i]) > m) m = fabs(v[i]);
    return m;
}

/* The rank of the k rows of C: singular values above tol. */
static int rank_rows(qp_ws *w, int k, double tol)
{
    int j, r = 0;
    const int n = w->n;
    if (svd_rows(w, k) < 0) return -1;
    for (j = 0; j < n; j++)
        if (w->S[j] > tol) r++;
    return r;
}

/* The minimiser under the equalities alone, from x (which satisfies them) into u and its
 * multipliers into lam: 0, or -1 when that fails. */
static int equality_minimiser(qp_ws *w, const double *H, const double *g, const double *A,
                              const double *x, double *u, double *lam)
{
    const int n = w->n, me = w->me;
    int i;
    if (me > 0) memcpy(w->C, A, (size_t)me * (size_t)n * sizeof(double));
    gradient(w, H, g, x, w->q);
    if (reduced_step(w, H, me, w->p) < 0) return -1;
    for (i = 0; i < n; i++) u[i] = x[i] + w->p[i];
    gradient(w, H, g, u, w->q);
    return lstsq_t(w, me, w->q, lam);
}

int tr_qp(int n, const double *H, const double *g, int me, const double *A, int mi, const double *G,
          const double *h, const double *x0, int max_iter, double *u, double *lam, double *mu,
          int *active, double *work)
{
    qp_ws w;
    int *ws = active; /* the working set's inequality indices, until the flags are set */
    int nw = 0, i, j, it, at_min = 0, have_y = 0, nact = 0;
    double scale, tol;
    if (n < 1 || n > TR_QP_MAX_N || me < 0 || mi < 0 || me + mi > TR_QP_MAX_ROWS || max_iter < 0)
        return TR_EINVAL;
    ws_init(&w, n, me, mi, work);
    memset(mu, 0, (size_t)mi * sizeof(double));
    memcpy(w.x, x0, (size_t)n * sizeof(double));
    /* the minimiser under the equalities alone, when it satisfies the inequalities too */
    if (equality_minimiser(&w, H, g, A, w.x, u, lam) == 0) {
        int ok = 1;
        for (i = 0; i < mi && ok; i++) {
            double s = 0.0;
            for (j = 0; j < n; j++) s += G[i * n + j] * u[j];
            ok = s >= h[i];
        }
        if (ok) {
            memset(active, 0, (size_t)mi * sizeof(int));
            return 0;
        }
    }
    for (i = 0; i < mi; i++) {
        double s = 0.0;
        for (j = 0; j < n; j++) s += G[i * n + j] * w.x[j];
        w.Gx[i] = s;
        w.h[i] = h[i] < s ? h[i] : s; /* relax what x0 violates */
        w.rowmax[i] = maxabs(G + (size_t)i * n, n);
    }
    scale = 1.0 + maxabs(w.Gx, mi) + maxabs(w.h, mi);
    tol = 1e-12 * scale;
    /* the starting working set: the active constraints that are independent */
    for (i = 0; i < mi; i++) {
        int k, r;
        double cmax;
        if (!(w.Gx[i] - w.h[i] <= tol)) continue;
        ws[nw] = i;
        k = stack_rows(&w, A, G, ws, nw + 1);
        cmax = maxabs(w.C, k * n);
        r = rank_rows(&w, k, 1e-10 * (cmax > 1e-300 ? cmax : 1e-300));
        if (r < 0) return TR_ESINGULAR;
        if (r == k) nw++;
    }
    for (it = 0; it < max_iter; it++) {
        const int k = stack_rows(&w, A, G, ws, nw);
        double pmax, alpha = 1.0;
        int block = -1;
        gradient(&w, H, g, w.x, w.q);
        if (at_min) {
            memset(w.p, 0, (size_t)n * sizeof(double));
        } else if (reduced_step(&w, H, k, w.p) < 0) {
            return TR_ESINGULAR;
        }
        at_min = 0;
        pmax = maxabs(w.p, n);
        if (pmax <= 1e-14 * (1.0 + maxabs(w.x, n))) {
            int leave = -1;
            double ymax;
            if (lstsq_t(&w, k, w.q, w.y) < 0) return TR_ESINGULAR;
            have_y = 1;
            ymax = maxabs(w.y, k);
            for (i = 0; i < nw; i++)
                if (w.y[me + i] < -1e-10 * (1.0 + ymax) && (leave < 0 || ws[i] < ws[leave]))
                    leave = i;
            if (leave < 0) break;
            for (i = leave; i < nw - 1; i++) ws[i] = ws[i + 1];
            nw--;
            have_y = 0;
            continue;
        }
        /* the longest step along p that keeps the inequalities outside the working set */
        for (i = 0; i < mi; i++) {
            double s = 0.0, gx = 0.0;
            int in_ws = 0;
            for (j = 0; j < n; j++) s += G[i * n + j] * w.p[j], gx += G[i * n + j] * w.x[j];
            w.Gp[i] = s;
            for (j = 0; j < nw && !in_ws; j++) in_ws = ws[j] == i;
            if (in_ws || !(s < -1e-14 * w.rowmax[i] * pmax)) {
                w.Gx[i] = NAN; /* not a candidate */
                continue;
            }
            w.Gx[i] = (w.h[i] - gx) / s;
            if (w.Gx[i] < 0.0) w.Gx[i] = 0.0;
            if (w.Gx[i] < alpha) alpha = w.Gx[i];
        }
        for (i = 0; i < mi && block < 0; i++)
            if (w.Gx[i] == w.Gx[i] && w.Gx[i] <= alpha * (1.0 + 1e-12)) block = i;
        for (j = 0; j < n; j++) w.x[j] += alpha * w.p[j];
        if (block >= 0) {
            ws[nw++] = block;
            have_y = 0;
        } else {
            at_min = 1;
        }
    }
    memcpy(u, w.x, (size_t)n * sizeof(double));
    if (have_y) {
        memcpy(lam, w.y, (size_t)me * sizeof(double));
        for (i = 0; i < nw; i++) mu[ws[i]] = w.y[me + i] > 0.0 ? w.y[me + i] : 0.0;
    } else {
        memset(lam, 0, (size_t)me * sizeof(double));
    }
    for (i = 0; i < mi; i++) {
        double s = 0.0;
        for (j = 0; j < n; j++) s += G[i * n + j] * u[j];
        active[i] = s - w.h[i] <= tol;
        nact += active[i];
    }
    return nact;
}

/* ------------------------------------------------------------------ least squares */
void tr_gauss_newton(int n, int m, const double *A, const double *r, double *H, double *g)
{
    double tr = 0.0;
    int i, j, l;
    for (i = 0; i < n; i++) {
        for (j = 0; j < n; j++) {
            double s = 0.0;
            for (l = 0; l < m; l++) s += A[l * n + i] * A[l * n + j];
            H[i * n + j] = s;
        }
        tr += H[i * n + i];
        g[i] = 0.0;
        for (l = 0; l < m; l++) g[i] += A[l * n + i] * r[l];
    }
    for (i = 0; i < n; i++) H[i * n + i] += 1e-12 * (tr / n + 1e-300);
}

double tr_lsq_cosine(int n, int m, const double *A, const double *r, int mi, const double *G,
                     const double *h)
{
    double rn = 0.0, worst = 0.0;
    int i, j, l;
    for (l = 0; l < m; l++) rn += r[l] * r[l];
    rn = sqrt(rn);
    for (j = 0; j < n; j++) {
        double g = 0.0, an = 0.0;
        int blocked = 0;
        for (l = 0; l < m; l++) {
            g += A[l * n + j] * r[l];
            an += A[l * n + j] * A[l * n + j];
        }
        for (i = 0; i < mi && !blocked; i++) blocked = G[i * n + j] * g > 0.0 && h[i] >= 0.0;
        if (!blocked && an > 0.0 && rn > 0.0) worst = fmax(worst, fabs(g) / (sqrt(an) * rn));
    }
    return worst;
}

void tr_bfgs_update(int n, double *H, const double *s, double *y, double *Hs)
{
    double sHs, sy;
    int i, j;
    for (i = 0; i < n; i++) {
        Hs[i] = 0.0;
        for (j = 0; j < n; j++) Hs[i] += H[i * n + j] * s[j];
    }
    sHs = 0.0;
    for (i = 0; i < n; i++) sHs += s[i] * Hs[i];
    if (!(sHs > 0.0)) return;
    sy = 0.0;
    for (i = 0; i < n; i++) sy += s[i] * y[i];
    if (sy < 0.2 * sHs) {
        const double th = 0.8 * sHs / (sHs - sy);
        for (i = 0; i < n; i++) y[i] = th * y[i] + (1.0 - th) * Hs[i];
        sy = 0.0;
        for (i = 0; i < n; i++) sy += s[i] * y[i];
    }
    for (i = 0; i < n; i++)
        for (j = 0; j < n; j++) H[i * n + j] += -Hs[i] * Hs[j] / sHs + y[i] * y[j] / sy;
}
