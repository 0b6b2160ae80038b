/*
 * tr_batch.c -- batch solves of one robot design (see tr_batch.h).
 *
 * Works through the solver's public API (tr_solve, tr_residual, tr_record and the
 * tr_model / tr_data structs): a private shallow copy of the base model owns the
 * value-carrying arrays (tendons, loads, breakpoint load sums) and is refilled per
 * point; everything else (breakpoints, routing, formulation, scales) is shared
 * read-only with the base model.  The workspace is allocated for the copy once, so
 * tr_solve sees a model whose address never changes.  Two dependencies go beyond the
 * public header and must follow the core if it changes: which model fields tr_solve
 * reads for loads and actuation (tendon[].value, bpF, bpM, dist, has_dist; load is
 * kept in step), and, when the recording pass is skipped, that d->y holds the tip
 * state of the last tr_residual evaluation, converted by tr_state_world
 * (tr_internal.h).  A public tr_model_set_values() and tr_tip_state() in the core
 * would remove both.
 */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tr_batch.h"
#include "tr_internal.h" /* tr_state_world: pose of a shooting state (see lean_newton) */

static void bmsg(char *msg, size_t msglen, const char *fmt, ...)
{
    va_list ap;
    if (!msg || msglen == 0) return;
    va_start(ap, fmt);
    vsnprintf(msg, msglen, fmt, ap);
    va_end(ap);
}

/* Workspace of one batch call: the private model copy and warm-start buffers. */
typedef struct batch_ws {
    tr_model mc;                      /* shallow copy of the base model; owns the arrays below */
    tr_tendon *tendon;                /* (nt) */
    double *load;                     /* (nl x 7) */
    double *bpF, *bpM;                /* (nseg + 1) x 3 */
    int *load_bp;                     /* (nl) breakpoint index of each point load */
    double *guess;                    /* (6 + 2 nt) physical guess from the last converged point */
    double *J;                        /* (k x k) its final scaled Jacobian */
    double *guess0;                   /* (6 + 2 nt) guess from the converged point before that */
    double *guess00;                  /* (6 + 2 nt) ... and the one before that */
    double *gp;                       /* (6 + 2 nt) predicted guess */
    double *P, *P1, *P0, *P00, *P000; /* (np) varied values of this point and of the last
                                  four converged points */
    double *guess000;                 /* (6 + 2 nt) guess of the fourth-last converged point */
    int np;                           /* number of varied values per point */
    double *X1, *X0, *X00, *X000;     /* (k) scaled unknowns of the last four converged points */
    double *lx, *lf, *lxt, *lft, *ldx, *lLU; /* (k), (k x k): lean Newton loop */
    double *xp;    /* (k) start of the lean loop (last or predicted unknowns) */
    double *Jsave; /* (k x k) w->J before a lean attempt (restored if it fails) */
    int *lpiv;     /* (k) pivots */
    int lean_J;    /* 1: J was maintained by the lean loop (not copied from d->J) */
    tr_data *d;
} batch_ws;

static void ws_free(batch_ws *w)
{
    tr_data_free(w->d);
    free(w->tendon);
    free(w->load);
    free(w->bpF);
    free(w->bpM);
    free(w->load_bp);
    free(w->guess);
    free(w->J);
    free(w->guess0);
    free(w->guess00);
    free(w->gp);
    free(w->P);
    free(w->P1);
    free(w->P0);
    free(w->P00);
    free(w->X1);
    free(w->X0);
    free(w->X00);
    free(w->X000);
    free(w->P000);
    free(w->guess000);
    free(w->lx);
    free(w->lf);
    free(w->lxt);
    free(w->lft);
    free(w->ldx);
    free(w->lLU);
    free(w->lpiv);
    free(w->xp);
    free(w->Jsave);
}

/* Nearest breakpoint to s (loads were snapped to a breakpoint within the merge
 * tolerance when the base model was compiled). */
static int nearest_bp(const tr_model *m, double s)
{
    int b, best = 0;
    double dmin = INFINITY;
    for (b = 0; b <= m->nseg; b++) {
        const double dd = fabs(m->bp[b] - s);
        if (dd < dmin) {
            dmin = dd;
            best = b;
        }
    }
    return best;
}

/* Physical guess [n(0) world, m(0) world, tension, slack] from the converged scaled
 * unknowns: the exact inverse of the map tr_solve_init applies to a guess (the
 * unknowns are the base reaction of the whole section, backbone plus tendon pulls). */
static void guess_from_solution(const tr_model *m, const tr_data *d, double *g)
{
    double tn[3] = {0, 0, 0}, tm[3] = {0, 0, 0};
    int i, c;
    for (i = 0; i < m->nt; i++) {
        const double tau = d->tension[i] > 0.0 ? d->tension[i] : 0.0;
        for (c = 0; c < 3; c++) {
            tn[c] += tau * m->tendon[i].t0[c];
            tm[c] += tau * m->tendon[i].rt0[c];
        }
        g[6 + i] = d->tension[i];
        g[6 + m->nt + i] = d->slack[i];
    }
    if (m->planar) {
        g[0] = d->x[0] * m->F_s - tn[0];
        g[1] = 0.0;
        g[2] = d->x[1] * m->F_s - tn[2];
        g[3] = 0.0;
        g[4] = d->x[2] * m->M_s - tm[1];
        g[5] = 0.0;
    } else {
        for (c = 0; c < 3; c++) {
            g[c] = d->x[c] * m->F_s - tn[c];
            g[3 + c] = d->x[3 + c] * m->M_s - tm[c];
        }
    }
}

/* The same guess computed the way tendonrod.Solution.base_state computes it from a
 * tip-only solution (solver.py, _base_from_unknowns): tendon tangents from cos/sin of
 * the routing angle and hypot(1, slope), the scales as EI/L^2 and EI/L.  Used in exact
 * mode so that a batch reproduces a loop of tr.solve(scene, guess=previous) bit for bit
 * (the core's own map, above, differs from it in the last bits). */
static void guess_like_python(const tr_model *m, const tr_data *d, double *g)
{
    double tn[3] = {0, 0, 0}, tm[3] = {0, 0, 0};
    const double Fs = m->EI / (m->L * m->L), Ms = m->EI / m->L;
    int i, c;
    for (i = 0; i < m->nt; i++) {
        const tr_tendon *t = &m->tendon[i];
        const double dv[3] = {cos(t->phi), sin(t->phi), 0.0};
        const double h = hypot(1.0, t->a);
        double t0[3], od[3], cr[3];
        const double tau = d->tension[i] > 0.0 ? d->tension[i] : 0.0;
        for (c = 0; c < 3; c++) t0[c] = (t->a * dv[c] + (c == 2 ? 1.0 : 0.0)) / h;
        for (c = 0; c < 3; c++) od[c] = t->b * dv[c];
        cr[0] = od[1] * t0[2] - od[2] * t0[1];
        cr[1] = od[2] * t0[0] - od[0] * t0[2];
        cr[2] = od[0] * t0[1] - od[1] * t0[0];
        for (c = 0; c < 3; c++) {
            tn[c] += tau * t0[c];
            tm[c] += tau * cr[c];
        }
        g[6 + i] = d->tension[i];
        g[6 + m->nt + i] = d->slack[i];
    }
    if (m->planar) {
        const double N[3] = {d->x[0] * Fs, 0.0 * Fs, d->x[1] * Fs};
        const double M[3] = {0.0 * Ms, d->x[2] * Ms, 0.0 * Ms};
        for (c = 0; c < 3; c++) {
            g[c] = N[c] - tn[c];
            g[3 + c] = M[c] - tm[c];
        }
    } else {
        for (c = 0; c < 3; c++) {
            g[c] = d->x[c] * Fs - tn[c];
            g[3 + c] = d->x[3 + c] * Ms - tm[c];
        }
    }
}

/* Fill the model copy with the values of point p; 0 or a message for TR_EINVAL. */
static int set_point(batch_ws *w, const tr_model *base, const tr_batch_in *in, int p, char *msg,
                     size_t msglen)
{
    tr_model *mc = &w->mc;
    const int nt = base->nt, nl = base->nl, nb = base->nseg + 1;
    int i, c;
    if (in->value) {
        const double *v = in->value + (size_t)p * nt;
        for (i = 0; i < nt; i++) {
            if (!isfinite(v[i])) {
                bmsg(msg, msglen, "point %d: tendon %d value %g is not finite", p, i, v[i]);
                return TR_EINVAL;
            }
            if (base->tendon[i].control == TR_TENSION && v[i] < 0.0) {
                bmsg(msg, msglen,
                     "point %d: tendon %d tension = %g N must be >= 0 (a tendon "
                     "cannot push)",
                     p, i, v[i]);
                return TR_EINVAL;
            }
            w->tendon[i].value = v[i];
        }
    }
    if (in->load) {
        const double *l = in->load + (size_t)p * nl * 6;
        for (i = 0; i < nl; i++) {
            for (c = 0; c < 6; c++) {
                if (!isfinite(l[6 * i + c])) {
                    bmsg(msg, msglen, "point %d: load %d component %d = %g is not finite", p, i, c,
                         l[6 * i + c]);
                    return TR_EINVAL;
                }
                w->load[7 * i + 1 + c] = l[6 * i + c];
            }
            if (base->planar &&
                (l[6 * i + 1] != 0.0 || l[6 * i + 3] != 0.0 || l[6 * i + 5] != 0.0)) {
                bmsg(msg, msglen,
                     "point %d: load %d leaves the x-z plane (Fy, Mx or Mz nonzero) but "
                     "the batch was compiled planar; compile it with force_spatial",
                     p, i);
                return TR_EINVAL;
            }
        }
        memset(w->bpF, 0, (size_t)3 * nb * sizeof(double));
        memset(w->bpM, 0, (size_t)3 * nb * sizeof(double));
        for (i = 0; i < nl; i++) {
            const int b = w->load_bp[i];
            for (c = 0; c < 3; c++) {
                w->bpF[3 * b + c] += w->load[7 * i + 1 + c];
                w->bpM[3 * b + c] += w->load[7 * i + 4 + c];
            }
        }
    }
    if (in->dist) {
        const double *dd = in->dist + (size_t)p * 3;
        for (c = 0; c < 3; c++)
            if (!isfinite(dd[c])) {
                bmsg(msg, msglen, "point %d: dist[%d] = %g is not finite", p, c, dd[c]);
                return TR_EINVAL;
            }
        if (base->planar && dd[1] != 0.0) {
            bmsg(msg, msglen,
                 "point %d: distributed load has a y component %g but the batch was "
                 "compiled planar; compile it with force_spatial",
                 p, dd[1]);
            return TR_EINVAL;
        }
        memcpy(mc->dist, dd, 3 * sizeof(double));
        mc->has_dist = (dd[0] != 0.0 || dd[1] != 0.0 || dd[2] != 0.0);
    }
    return TR_OK;
}

/* The varied values of point p, concatenated (values, loads, dist as given). */
static void gather(const tr_model *m, const tr_batch_in *in, int p, double *P)
{
    int o = 0, i;
    if (in->value)
        for (i = 0; i < m->nt; i++) P[o++] = in->value[(size_t)p * m->nt + i];
    if (in->load)
        for (i = 0; i < 6 * m->nl; i++) P[o++] = in->load[(size_t)p * 6 * m->nl + i];
    if (in->dist)
        for (i = 0; i < 3; i++) P[o++] = in->dist[(size_t)p * 3 + i];
}

/* c with b = c a (to 1e-9 relative), 0 < c <= 2; 0 if b is not such a multiple of a. */
static double collinear(const double *b1, const double *b0, const double *a1, const double *a0,
                        int np)
{
    double dd = 0.0, dp = 0.0, pp = 0.0, rr = 0.0, c;
    int i;
    for (i = 0; i < np; i++) {
        const double a = a1[i] - a0[i], b = b1[i] - b0[i];
        dd += a * a;
        dp += a * b;
        pp += b * b;
    }
    if (!(dd > 0.0) || !(pp > 0.0)) return 0.0;
    c = dp / dd;
    if (!(c > 0.0 && c <= 2.0)) return 0.0;
    for (i = 0; i < np; i++) {
        const double e = (b1[i] - b0[i]) - c * (a1[i] - a0[i]);
        rr += e * e;
    }
    return rr <= 1e-18 * pp ? c : 0.0;
}

/* Predictor along a line of points: if this point continues the line through the last
 * converged points, extrapolate their solutions (Lagrange in the line parameter): cubic
 * through four equally spaced points (start error O(h^4)), else quadratic through three
 * (O(h^3)), else the secant through two (O(h^2)).  have = number of consecutive
 * converged points on record (<= 4).  Sets the weights of (last, the one before, ...)
 * and returns the order used (0: none).  Measured on the 100-point lines of the
 * throughput benchmark (h = 2 % of EI/L^2): start residual ~2e-2 (none), ~1e-4
 * (secant), ~2e-6 (quadratic); Newton/Broyden iterations per point 2.35 (quadratic)
 * -> 1.5 (cubic). */
static int predict_weights(const batch_ws *w, int have, double wt[4])
{
    const double c = have >= 2 ? collinear(w->P, w->P1, w->P1, w->P0, w->np) : 0.0;
    double c2 = 0.0;
    wt[3] = 0.0;
    if (c == 0.0) return 0;
    if (have >= 3) c2 = collinear(w->P1, w->P0, w->P0, w->P00, w->np);
    if (have >= 4 && fabs(c - 1.0) <= 1e-9 && fabs(c2 - 1.0) <= 1e-9 &&
        fabs(collinear(w->P0, w->P00, w->P00, w->P000, w->np) - 1.0) <= 1e-9) {
        /* equally spaced: cubic through four points, start error O(h^4) */
        wt[0] = 4.0;
        wt[1] = -6.0;
        wt[2] = 4.0;
        wt[3] = -1.0;
        return 3;
    }
    if (c2 >= 0.5) {
        /* nodes t = 0 (last), -1, -(1 + 1/c2); target t = c */
        const double ta = 0.0, tb = -1.0, tc = -(1.0 + 1.0 / c2), T = c;
        wt[0] = (T - tb) * (T - tc) / ((ta - tb) * (ta - tc));
        wt[1] = (T - ta) * (T - tc) / ((tb - ta) * (tb - tc));
        wt[2] = (T - ta) * (T - tb) / ((tc - ta) * (tc - tb));
        return 2;
    }
    wt[0] = 1.0 + c;
    wt[1] = -c;
    wt[2] = 0.0;
    return 1;
}

static void extrapolate(const double wt[4], const double *a, const double *b, const double *c,
                        const double *e, double *out, int n)
{
    int i;
    for (i = 0; i < n; i++)
        out[i] = wt[0] * a[i] + wt[1] * b[i] + (wt[2] != 0.0 ? wt[2] * c[i] : 0.0) +
                 (wt[3] != 0.0 ? wt[3] * e[i] : 0.0);
}

static double maxabs(const double *v, int n)
{
    double r = 0.0;
    int i;
    for (i = 0; i < n; i++) {
        const double a = fabs(v[i]);
        if (!(a <= r)) r = a; /* NaN propagates */
    }
    return r;
}

/* LU with partial pivoting of the n x n row-major A in place; 0, or -1 if singular. */
static int lu_factor(double *A, int *piv, int n)
{
    int i, j, c;
    for (c = 0; c < n; c++) {
        int pr = c;
        double best = fabs(A[c * n + c]);
        for (i = c + 1; i < n; i++)
            if (fabs(A[i * n + c]) > best) {
                best = fabs(A[i * n + c]);
                pr = i;
            }
        if (!(best > 0.0)) return -1;
        piv[c] = pr;
        if (pr != c)
            for (j = 0; j < n; j++) {
                const double t = A[c * n + j];
                A[c * n + j] = A[pr * n + j];
                A[pr * n + j] = t;
            }
        for (i = c + 1; i < n; i++) {
            const double l = A[i * n + c] / A[c * n + c];
            A[i * n + c] = l;
            for (j = c + 1; j < n; j++) A[i * n + j] -= l * A[c * n + j];
        }
    }
    return 0;
}

static void lu_apply(const double *A, const int *piv, int n, double *b)
{
    int i, j;
    for (i = 0; i < n; i++) {
        if (piv[i] != i) {
            const double t = b[i];
            b[i] = b[piv[i]];
            b[piv[i]] = t;
        }
        for (j = 0; j < i; j++) b[i] -= A[i * n + j] * b[j];
    }
    for (i = n - 1; i >= 0; i--) {
        for (j = i + 1; j < n; j++) b[i] -= A[i * n + j] * b[j];
        b[i] /= A[i * n + i];
    }
}

/* Smallest step (scaled max-norm) that updates the Jacobian: below it the secant
 * (f(x + dx) - f(x)) / dx is dominated by the integration's round-off (~1e-14) and
 * a Broyden update would spoil a Jacobian that later points reuse. */
#define TR_BATCH_BROYDEN_MIN_STEP 1e-10

/* Lean warm solve at fixed steps through the public residual: Newton steps with the
 * carried Jacobian w->J from the (predicted) unknowns x0, good-Broyden updates guarded
 * against round-off, no line search (a step that does not reduce the residual
 * max-norm ends the attempt), then the tip recording.  Any failure returns < 0 and the
 * caller runs tr_solve. */
static int lean_newton(batch_ws *w, tr_model *mc, tr_data *d, const double *x0, int max_iter,
                       int record)
{
    const int k = d->k;
    double *x = w->lx, *f = w->lf, *xt = w->lxt, *ft = w->lft, *dx = w->ldx, *J = w->J;
    double fn, fnt;
    int i, j, st;
    d->nit = d->nfev = d->njev = d->cont_steps = 0;
    d->steps_moved = 0;
    d->message[0] = '\0';
    d->lam_act = d->lam_load = 1.0;
    d->truncation = NAN;
    d->jacobian_cond = NAN;
    d->probe_bp = -1;
    d->steps = d->opt.steps;
    if (mc->scene_status != TR_OK) return mc->scene_status;
    memcpy(x, x0, (size_t)k * sizeof(double));
    if (tr_residual(mc, d, x, f) != TR_OK) return TR_ENONFINITE;
    fn = maxabs(f, k);
    while (!(fn <= d->opt.tol)) {
        double ss = 0.0;
        if (d->nit >= max_iter || d->nfev >= d->opt.max_nfev) return TR_EMAXITER;
        memcpy(w->lLU, J, (size_t)k * k * sizeof(double));
        if (lu_factor(w->lLU, w->lpiv, k) != 0) return TR_ESINGULAR;
        for (i = 0; i < k; i++) dx[i] = -f[i];
        lu_apply(w->lLU, w->lpiv, k, dx);
        for (i = 0; i < k; i++) xt[i] = x[i] + dx[i];
        st = tr_residual(mc, d, xt, ft);
        fnt = st == TR_OK ? maxabs(ft, k) : INFINITY;
        if (!(fnt < fn)) return TR_ENOPROGRESS;
        for (i = 0; i < k; i++) ss += dx[i] * dx[i];
        if (maxabs(dx, k) > TR_BATCH_BROYDEN_MIN_STEP) {
            /* J += (ft - f - J dx) dx^T / (dx^T dx) */
            for (i = 0; i < k; i++) {
                double r = ft[i] - f[i];
                for (j = 0; j < k; j++) r -= J[i * k + j] * dx[j];
                r /= ss;
                for (j = 0; j < k; j++) J[i * k + j] += r * dx[j];
            }
        }
        memcpy(x, xt, (size_t)k * sizeof(double));
        memcpy(f, ft, (size_t)k * sizeof(double));
        fn = fnt;
        d->nit++;
    }
    memcpy(d->x, x, (size_t)k * sizeof(double));
    memcpy(d->f, f, (size_t)k * sizeof(double));
    d->fnorm = d->residual_norm = fn;
    if (record) {
        st = tr_record(mc, d);
        if (st != TR_OK) return st;
    } else {
        /* The last residual evaluation was at the converged x (every accepted step is
         * the last evaluation), so d->y holds its tip state and d->tau, d->beta its
         * tensions and slacks; the recording pass would reproduce exactly this tip (it
         * replaces its tip node by the shooting tip).  Only the actuator displacement
         * of a tension-controlled tendon needs the recording pass (its path length is
         * not a shooting state): NaN here. */
        double nw[3], mw[3];
        int i;
        tr_state_world(mc, d->y, d->pos, d->rot, nw, mw);
        for (i = 0; i < mc->nt; i++) {
            d->tension[i] = d->tau[i];
            d->slack[i] = d->beta[i];
            d->displacement[i] =
                mc->tendon[i].control == TR_DISPLACEMENT ? mc->tendon[i].value : NAN;
        }
    }
    return d->status = TR_OK;
}

/* Iterations a fast warm solve may take before the point goes to tr_solve. */
#define TR_BATCH_FAST_ITER 8

int tr_batch_solve(const tr_model *m, const tr_options *opt, const tr_batch_in *in,
                   tr_batch_out *out, char *msg, size_t msglen)
{
    batch_ws w;
    tr_options o;
    int p, i, k, nt, have_prev = 0, record = 1;
    if (!m || !opt || !in || !out) {
        bmsg(msg, msglen, "tr_batch_solve: NULL argument");
        return TR_EINVAL;
    }
    if (in->n < 0) {
        bmsg(msg, msglen, "tr_batch_solve: n = %d must be >= 0", in->n);
        return TR_EINVAL;
    }
    if (!out->tip_pos || !out->tip_rot || !out->residual || !out->status || !out->nit ||
        !out->nfev || (m->nt > 0 && (!out->tension || !out->slack || !out->displacement))) {
        bmsg(msg, msglen, "tr_batch_solve: an output array is NULL");
        return TR_EINVAL;
    }
    if (in->n == 0) return TR_OK;
    nt = m->nt;
    memset(&w, 0, sizeof w);
    w.mc = *m;
    w.tendon = (tr_tendon *)malloc((size_t)(nt > 0 ? nt : 1) * sizeof(tr_tendon));
    w.load = (double *)malloc((size_t)(m->nl > 0 ? 7 * m->nl : 1) * sizeof(double));
    w.bpF = (double *)malloc((size_t)3 * (m->nseg + 1) * sizeof(double));
    w.bpM = (double *)malloc((size_t)3 * (m->nseg + 1) * sizeof(double));
    w.load_bp = (int *)malloc((size_t)(m->nl > 0 ? m->nl : 1) * sizeof(int));
    w.guess = (double *)malloc((size_t)(6 + 2 * nt) * sizeof(double));
    k = m->n_unknowns;
    w.J = (double *)malloc((size_t)(k > 0 ? k * k : 1) * sizeof(double));
    w.np = (in->value ? nt : 0) + (in->load ? 6 * m->nl : 0) + (in->dist ? 3 : 0);
    w.guess0 = (double *)malloc((size_t)(6 + 2 * nt) * sizeof(double));
    w.guess00 = (double *)malloc((size_t)(6 + 2 * nt) * sizeof(double));
    w.P00 = (double *)malloc((size_t)(w.np > 0 ? w.np : 1) * sizeof(double));
    w.P000 = (double *)malloc((size_t)(w.np > 0 ? w.np : 1) * sizeof(double));
    w.guess000 = (double *)malloc((size_t)(6 + 2 * nt) * sizeof(double));
    w.gp = (double *)malloc((size_t)(6 + 2 * nt) * sizeof(double));
    w.P = (double *)malloc((size_t)(w.np > 0 ? w.np : 1) * sizeof(double));
    w.P1 = (double *)malloc((size_t)(w.np > 0 ? w.np : 1) * sizeof(double));
    w.P0 = (double *)malloc((size_t)(w.np > 0 ? w.np : 1) * sizeof(double));
    {
        const size_t kk = (size_t)(k > 0 ? k : 1);
        w.X1 = (double *)malloc(kk * sizeof(double));
        w.X0 = (double *)malloc(kk * sizeof(double));
        w.X00 = (double *)malloc(kk * sizeof(double));
        w.X000 = (double *)malloc(kk * sizeof(double));
        w.lx = (double *)malloc(kk * sizeof(double));
        w.lf = (double *)malloc(kk * sizeof(double));
        w.lxt = (double *)malloc(kk * sizeof(double));
        w.lft = (double *)malloc(kk * sizeof(double));
        w.ldx = (double *)malloc(kk * sizeof(double));
        w.lLU = (double *)malloc(kk * kk * sizeof(double));
        w.lpiv = (int *)malloc(kk * sizeof(int));
        w.xp = (double *)malloc(kk * sizeof(double));
        w.Jsave = (double *)malloc(kk * kk * sizeof(double));
    }
    if (!w.X1 || !w.X0 || !w.X00 || !w.X000 || !w.P000 || !w.guess000 || !w.lx || !w.lf || !w.lxt ||
        !w.lft || !w.ldx || !w.lLU || !w.lpiv || !w.xp || !w.Jsave || !w.tendon || !w.load ||
        !w.bpF || !w.bpM || !w.load_bp || !w.guess || !w.J || !w.guess0 || !w.guess00 || !w.gp ||
        !w.P || !w.P1 || !w.P0 || !w.P00) {
        ws_free(&w);
        bmsg(msg, msglen, "out of memory while setting up the batch");
        return TR_ENOMEM;
    }
    if (nt > 0) memcpy(w.tendon, m->tendon, (size_t)nt * sizeof(tr_tendon));
    if (m->nl > 0) memcpy(w.load, m->load, (size_t)7 * m->nl * sizeof(double));
    memcpy(w.bpF, m->bpF, (size_t)3 * (m->nseg + 1) * sizeof(double));
    memcpy(w.bpM, m->bpM, (size_t)3 * (m->nseg + 1) * sizeof(double));
    for (i = 0; i < m->nl; i++) w.load_bp[i] = nearest_bp(m, m->load[7 * i]);
    w.mc.tendon = w.tendon;
    w.mc.load = w.load;
    w.mc.bpF = w.bpF;
    w.mc.bpM = w.bpM;
    o = *opt;
    o.tip_only = 1;
    w.d = tr_data_alloc(&w.mc, &o, 1, NULL, msg, msglen);
    if (!w.d) {
        ws_free(&w);
        return TR_ENOMEM;
    }

    {
        int nten = 0;
        for (i = 0; i < nt; i++) nten += m->tendon[i].control == TR_TENSION;
        /* the recording pass adds nothing unless a tension-controlled tendon's
         * displacement is wanted */
        record = nten > 0 && !in->skip_tension_displacement;
    }
    for (p = 0; p < in->n; p++) {
        tr_data *d = w.d;
        int st, nit, nfev, cold, lean;
        char pmsg[TR_MSGLEN];
        st = set_point(&w, m, in, p, pmsg, sizeof pmsg);
        if (st != TR_OK) {
            for (i = 0; i < 3; i++) out->tip_pos[3 * p + i] = NAN;
            for (i = 0; i < 9; i++) out->tip_rot[9 * p + i] = NAN;
            for (i = 0; i < nt; i++)
                out->tension[nt * p + i] = out->slack[nt * p + i] = out->displacement[nt * p + i] =
                    NAN;
            out->residual[p] = NAN;
            out->status[p] = st;
            out->nit[p] = out->nfev[p] = 0;
            if (out->cold) out->cold[p] = 1;
            if (out->message) bmsg(out->message + (size_t)p * out->msglen, out->msglen, "%s", pmsg);
            continue;
        }
        cold = !(in->warm && have_prev);
        gather(m, in, p, w.P);
        lean = 0;
        {
            const double *g = w.guess;
            double wt[4];
            int fast = 0;
            if (have_prev >= 1) memcpy(w.xp, w.X1, (size_t)k * sizeof(double));
            if (!cold && !in->exact && have_prev >= 2 && in->predict &&
                predict_weights(&w, have_prev, wt) > 0) {
                extrapolate(wt, w.guess, w.guess0, w.guess00, w.guess000, w.gp, 6 + 2 * nt);
                extrapolate(wt, w.X1, w.X0, w.X00, w.X000, w.xp, k);
                g = w.gp;
            }
            if (!cold && !in->exact && d->opt.steps > 0 && d->opt.integrator != TR_ADAPTIVE) {
                memcpy(w.Jsave, w.J, (size_t)k * k * sizeof(double)); /* restored on failure */
                st = lean_newton(&w, &w.mc, d, w.xp,
                                 d->opt.max_iter < TR_BATCH_FAST_ITER ? d->opt.max_iter
                                                                      : TR_BATCH_FAST_ITER,
                                 record);
                fast = lean = st == TR_OK;
                if (!fast) memcpy(w.J, w.Jsave, (size_t)k * k * sizeof(double));
                nit = d->nit;
                nfev = d->nfev;
            } else {
                nit = nfev = 0;
            }
            if (!fast) {
                st = tr_solve(&w.mc, d, cold ? NULL : g, cold ? NULL : w.J);
                nit += d->nit;
                nfev += d->nfev;
            }
        }
        if (st < 0 && !cold && in->retry_cold) {
            st = tr_solve(&w.mc, d, NULL, NULL);
            nit += d->nit;
            nfev += d->nfev;
            cold = 1;
        }
        memcpy(out->tip_pos + 3 * p, d->pos, 3 * sizeof(double));
        memcpy(out->tip_rot + 9 * p, d->rot, 9 * sizeof(double));
        if (nt > 0) {
            memcpy(out->tension + (size_t)nt * p, d->tension, (size_t)nt * sizeof(double));
            memcpy(out->slack + (size_t)nt * p, d->slack, (size_t)nt * sizeof(double));
            memcpy(out->displacement + (size_t)nt * p, d->displacement,
                   (size_t)nt * sizeof(double));
        }
        out->residual[p] = d->residual_norm;
        out->status[p] = st;
        out->nit[p] = nit;
        out->nfev[p] = nfev;
        if (out->cold) out->cold[p] = cold;
        if (st != TR_OK && out->message)
            bmsg(out->message + (size_t)p * out->msglen, out->msglen, "%s", d->message);
        if (st >= 0) {
            if (have_prev >= 3) {
                memcpy(w.guess000, w.guess00, (size_t)(6 + 2 * nt) * sizeof(double));
                memcpy(w.P000, w.P00, (size_t)w.np * sizeof(double));
                memcpy(w.X000, w.X00, (size_t)k * sizeof(double));
            }
            if (have_prev >= 2) {
                memcpy(w.guess00, w.guess0, (size_t)(6 + 2 * nt) * sizeof(double));
                memcpy(w.P00, w.P0, (size_t)w.np * sizeof(double));
            }
            if (have_prev >= 1) {
                memcpy(w.guess0, w.guess, (size_t)(6 + 2 * nt) * sizeof(double));
                memcpy(w.P0, w.P1, (size_t)w.np * sizeof(double));
            }
            if (in->exact)
                guess_like_python(&w.mc, d, w.guess);
            else
                guess_from_solution(&w.mc, d, w.guess);
            memcpy(w.P1, w.P, (size_t)w.np * sizeof(double));
            if (have_prev >= 2) memcpy(w.X00, w.X0, (size_t)k * sizeof(double));
            if (have_prev >= 1) memcpy(w.X0, w.X1, (size_t)k * sizeof(double));
            memcpy(w.X1, d->x, (size_t)k * sizeof(double));
            if (!lean) /* the lean loop kept its own (guarded) updates in w.J */
                memcpy(w.J, d->J, (size_t)k * k * sizeof(double));
            have_prev = have_prev < 4 ? have_prev + 1 : 4;
        } else {
            have_prev = have_prev > 0 ? 1 : 0; /* no extrapolation across a failed point */
        }
    }
    ws_free(&w);
    return TR_OK;
}
