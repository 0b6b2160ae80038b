/*
 * tr_batch.c -- batch solves of one robot design (see tr_batch.h).
 *
 * Works through the public solver API only: a private shallow copy of the base
 * model owns the value-carrying arrays (tendons, loads, breakpoint load sums) and
 * is refilled per point; everything else (breakpoints, routing, formulation,
 * scales) is shared read-only with the base model.  The workspace is allocated for
 * the copy once, so tr_solve sees a model whose address never changes.
 */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tr_batch.h"

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
    tr_model mc;            /* shallow copy of the base model; owns the arrays below */
    tr_tendon *tendon;      /* (nt) */
    double *load;           /* (nl x 7) */
    double *bpF, *bpM;      /* (nseg + 1) x 3 */
    int *load_bp;           /* (nl) breakpoint index of each point load */
    double *guess;          /* (6 + 2 nt) physical guess from the last converged point */
    double *J;              /* (k x k) its final scaled Jacobian */
    double *guess0;         /* (6 + 2 nt) guess from the converged point before that */
    double *guess00;        /* (6 + 2 nt) ... and the one before that */
    double *gp;             /* (6 + 2 nt) predicted guess */
    double *P, *P1, *P0, *P00; /* (np) varied values of this point and of the last three
                                  converged points */
    int np;                 /* number of varied values per point */
    tr_data *d;
    double s_tip;           /* the workspace's tip node arc length (restored before every
                               solve: a failed recording pass overwrites d->s with NaN) */
} batch_ws;

static void ws_free(batch_ws *w)
{
    tr_data_free(w->d);
    free(w->tendon); free(w->load); free(w->bpF); free(w->bpM);
    free(w->load_bp); free(w->guess); free(w->J);
    free(w->guess0); free(w->guess00); free(w->gp); free(w->P); free(w->P1); free(w->P0);
    free(w->P00);
}

/* Nearest breakpoint to s (loads were snapped to a breakpoint within the merge
 * tolerance when the base model was compiled). */
static int nearest_bp(const tr_model *m, double s)
{
    int b, best = 0;
    double dmin = INFINITY;
    for (b = 0; b <= m->nseg; b++) {
        const double dd = fabs(m->bp[b] - s);
        if (dd < dmin) { dmin = dd; best = b; }
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
        for (c = 0; c < 3; c++) { g[c] = N[c] - tn[c]; g[3 + c] = M[c] - tm[c]; }
    } else {
        for (c = 0; c < 3; c++) {
            g[c] = d->x[c] * Fs - tn[c];
            g[3 + c] = d->x[3 + c] * Ms - tm[c];
        }
    }
}

/* Fill the model copy with the values of point p; 0 or a message for TR_EINVAL. */
static int set_point(batch_ws *w, const tr_model *base, const tr_batch_in *in, int p,
                     char *msg, size_t msglen)
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
                bmsg(msg, msglen, "point %d: tendon %d tension = %g N must be >= 0 (a tendon "
                     "cannot push)", p, i, v[i]);
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
            if (base->planar && (l[6 * i + 1] != 0.0 || l[6 * i + 3] != 0.0 || l[6 * i + 5] != 0.0)) {
                bmsg(msg, msglen, "point %d: load %d leaves the x-z plane (Fy, Mx or Mz nonzero) but "
                     "the batch was compiled planar; compile it with force_spatial", p, i);
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
            bmsg(msg, msglen, "point %d: distributed load has a y component %g but the batch was "
                 "compiled planar; compile it with force_spatial", p, dd[1]);
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
static double collinear(const double *b1, const double *b0, const double *a1, const double *a0, int np)
{
    double dd = 0.0, dp = 0.0, pp = 0.0, rr = 0.0, c;
    int i;
    for (i = 0; i < np; i++) {
        const double a = a1[i] - a0[i], b = b1[i] - b0[i];
        dd += a * a;
        dp += a * b;
        pp += b * b;
    }
    if (!(dd > 0.0) || !(pp > 0.0))
        return 0.0;
    c = dp / dd;
    if (!(c > 0.0 && c <= 2.0))
        return 0.0;
    for (i = 0; i < np; i++) {
        const double e = (b1[i] - b0[i]) - c * (a1[i] - a0[i]);
        rr += e * e;
    }
    return rr <= 1e-18 * pp ? c : 0.0;
}

/* Predictor along a line of points: if this point continues the line through the last
 * converged points, extrapolate their guesses (Lagrange in the line parameter):
 * quadratic through three points (start error O(h^3)), else the secant through two
 * (O(h^2)).  have = number of consecutive converged points on record (<= 3).  Returns
 * the order used (0: none, gp unset). */
static int predict(const batch_ws *w, int ng, int have)
{
    const double c = have >= 2 ? collinear(w->P, w->P1, w->P1, w->P0, w->np) : 0.0;
    double c2 = 0.0;
    int i;
    if (c == 0.0)
        return 0;
    if (have >= 3)
        c2 = collinear(w->P1, w->P0, w->P0, w->P00, w->np);
    if (c2 >= 0.5) {
        /* nodes t = 0 (g1), -1 (g0), -(1 + 1/c2) (g00); target t = c */
        const double ta = 0.0, tb = -1.0, tc = -(1.0 + 1.0 / c2), T = c;
        const double wa = (T - tb) * (T - tc) / ((ta - tb) * (ta - tc));
        const double wb = (T - ta) * (T - tc) / ((tb - ta) * (tb - tc));
        const double wc = (T - ta) * (T - tb) / ((tc - ta) * (tc - tb));
        for (i = 0; i < ng; i++)
            w->gp[i] = wa * w->guess[i] + wb * w->guess0[i] + wc * w->guess00[i];
        return 2;
    }
    for (i = 0; i < ng; i++)
        w->gp[i] = w->guess[i] + c * (w->guess[i] - w->guess0[i]);
    return 1;
}

/* Warm solve at fixed steps through the public step API: init from the guess and the
 * previous Jacobian, damped Newton/Broyden iterations to tol, then the tip recording.
 * No step verification (the step count is fixed), no continuation, no polish; at most
 * max_iter iterations (the caller falls back to tr_solve on any failure). */
static int fast_warm(tr_model *mc, tr_data *d, const double *guess, const double *J, int max_iter)
{
    int st;
    d->nit = d->nfev = d->njev = d->cont_steps = 0;
    d->steps_moved = 0;
    d->message[0] = '\0';
    d->lam_act = d->lam_load = 1.0;
    d->truncation = NAN;
    d->jacobian_cond = NAN;
    d->probe_bp = -1;
    d->steps = d->opt.steps;
    if (mc->scene_status != TR_OK)
        return mc->scene_status;
    st = tr_solve_init(mc, d, guess, J);
    if (st != TR_OK)
        return st < 0 ? st : TR_ENONFINITE;
    while ((st = tr_solve_test(mc, d)) == TR_CONTINUE) {
        if (d->nit >= max_iter)
            return TR_EMAXITER;
        st = tr_solve_iterate(mc, d);
        if (st != TR_CONTINUE)
            return st < 0 ? st : TR_ENOPROGRESS;
    }
    d->residual_norm = d->fnorm;
    st = tr_record(mc, d);
    if (st != TR_OK)
        return st;
    return d->status = TR_OK;
}

/* Iterations a fast warm solve may take before the point goes to tr_solve. */
#define TR_BATCH_FAST_ITER 8

int tr_batch_solve(const tr_model *m, const tr_options *opt, const tr_batch_in *in,
                   tr_batch_out *out, char *msg, size_t msglen)
{
    batch_ws w;
    tr_options o;
    int p, i, k, nt, have_prev = 0;
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
    w.gp = (double *)malloc((size_t)(6 + 2 * nt) * sizeof(double));
    w.P = (double *)malloc((size_t)(w.np > 0 ? w.np : 1) * sizeof(double));
    w.P1 = (double *)malloc((size_t)(w.np > 0 ? w.np : 1) * sizeof(double));
    w.P0 = (double *)malloc((size_t)(w.np > 0 ? w.np : 1) * sizeof(double));
    if (!w.tendon || !w.load || !w.bpF || !w.bpM || !w.load_bp || !w.guess || !w.J ||
        !w.guess0 || !w.guess00 || !w.gp || !w.P || !w.P1 || !w.P0 || !w.P00) {
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
    w.s_tip = w.d->s[0];

    for (p = 0; p < in->n; p++) {
        tr_data *d = w.d;
        int st, nit, nfev, cold;
        char pmsg[TR_MSGLEN];
        st = set_point(&w, m, in, p, pmsg, sizeof pmsg);
        if (st != TR_OK) {
            for (i = 0; i < 3; i++) out->tip_pos[3 * p + i] = NAN;
            for (i = 0; i < 9; i++) out->tip_rot[9 * p + i] = NAN;
            for (i = 0; i < nt; i++)
                out->tension[nt * p + i] = out->slack[nt * p + i] = out->displacement[nt * p + i] = NAN;
            out->residual[p] = NAN;
            out->status[p] = st;
            out->nit[p] = out->nfev[p] = 0;
            if (out->cold) out->cold[p] = 1;
            if (out->message) bmsg(out->message + (size_t)p * out->msglen, out->msglen, "%s", pmsg);
            continue;
        }
        cold = !(in->warm && have_prev);
        gather(m, in, p, w.P);
        d->s[0] = w.s_tip;
        {
            const double *g = w.guess;
            int fast = 0;
            if (!cold && !in->exact && have_prev >= 2 && in->predict &&
                predict(&w, 6 + 2 * nt, have_prev))
                g = w.gp;
            if (!cold && !in->exact && d->opt.steps > 0 && d->opt.integrator != TR_ADAPTIVE) {
                st = fast_warm(&w.mc, d, g, w.J, d->opt.max_iter < TR_BATCH_FAST_ITER ?
                               d->opt.max_iter : TR_BATCH_FAST_ITER);
                fast = st == TR_OK;
                nit = d->nit;
                nfev = d->nfev;
            } else {
                nit = nfev = 0;
            }
            if (!fast) {
                d->s[0] = w.s_tip;
                st = tr_solve(&w.mc, d, cold ? NULL : g, cold ? NULL : w.J);
                nit += d->nit;
                nfev += d->nfev;
            }
        }
        if (st < 0 && !cold && in->retry_cold) {
            d->s[0] = w.s_tip;
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
            memcpy(out->displacement + (size_t)nt * p, d->displacement, (size_t)nt * sizeof(double));
        }
        out->residual[p] = d->residual_norm;
        out->status[p] = st;
        out->nit[p] = nit;
        out->nfev[p] = nfev;
        if (out->cold) out->cold[p] = cold;
        if (st != TR_OK && out->message)
            bmsg(out->message + (size_t)p * out->msglen, out->msglen, "%s", d->message);
        if (st >= 0) {
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
            memcpy(w.J, d->J, (size_t)k * k * sizeof(double));
            have_prev = have_prev < 3 ? have_prev + 1 : 3;
        } else {
            have_prev = have_prev > 0 ? 1 : 0;   /* no extrapolation across a failed point */
        }
    }
    ws_free(&w);
    return TR_OK;
}
