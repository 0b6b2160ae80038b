/*
 * tr_batch.c -- batch solves of one robot design (see tr_batch.h): a loop over the
 * core's public API.  The base model is shared read-only (several threads may run
 * batches of one model at once); each point's values are set in the one workspace that
 * serves every point (tr_data_set_values).  A warm point starts from the last converged one (its base state by
 * tr_base_state, its unknowns and Jacobian) or from an extrapolation along the line
 * of the last converged points; a point off that line starts from the nearer (in scaled
 * values) of the last converged point and the first point of the last line (the anchor:
 * on a grid swept line by line, the neighbour of the next line's first point).  With a
 * fixed step count it first tries the lean solve (tr_solve_lean), then the full tr_solve.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tr_batch.h"
#include "tr_internal.h"

/* Workspace of one batch call. */
typedef struct batch_ws {
    const tr_model *m;             /* the base model, shared read-only */
    tr_data *d;                    /* the one workspace */
    int k, ng, np;                 /* unknowns; guess length 6 + 2 nt; varied values */
    double *hist_g[TR_BATCH_HIST]; /* (ng) base states of the last converged points, newest first */
    double *hist_x[TR_BATCH_HIST]; /* (k) their scaled unknowns */
    double *hist_p[TR_BATCH_HIST]; /* (np) their varied values */
    double *P;                     /* (np) varied values of this point */
    double *gp, *xp;               /* (ng), (k) predicted base state and unknowns */
    double *hist_J[TR_BATCH_HIST]; /* (k x k) their final Jacobians */
    double *ag, *ax, *ap, *aJ;     /* the anchor: base state, unknowns, values, Jacobian */
    double *scale;                 /* (np) scale of each varied value (its size in the
                                      verdict's scaled values) */
    int run;                       /* converged points on the line through the newest */
    int have_anchor;
    tr_verified ver; /* its step verification (ver.x: (k), steps 0: none) */
    double *xver;    /* (k) the unknowns behind ver.x */
    double *vver;    /* (nt) the actuation values behind ver.values */
    double *block;   /* the one allocation behind the arrays above */
} batch_ws;

static void ws_free(batch_ws *w)
{
    tr_data_free(w->d);
    free(w->block);
}

static int ws_alloc(batch_ws *w, const tr_model *base, const tr_options *opt, int np, char *msg,
                    size_t msglen)
{
    tr_options o = *opt;
    size_t len;
    double *q;
    int h;
    memset(w, 0, sizeof *w);
    w->k = base->n_unknowns;
    w->ng = 6 + 2 * base->nt;
    w->np = np;
    len = (size_t)(TR_BATCH_HIST + 1) * (w->ng + w->k + np + (size_t)w->k * w->k) + 2 * np + w->ng +
          2 * (size_t)w->k + (size_t)base->nt;
    w->block = (double *)calloc(len + 1, sizeof(double));
    w->m = base;
    if (!w->block) {
        tr_msgf(msg, msglen, "out of memory while setting up the batch");
        return TR_ENOMEM;
    }
    q = w->block;
    for (h = 0; h < TR_BATCH_HIST; h++) {
        w->hist_g[h] = q, q += w->ng;
        w->hist_x[h] = q, q += w->k;
        w->hist_p[h] = q, q += np;
        w->hist_J[h] = q, q += (size_t)w->k * w->k;
    }
    w->ag = q, q += w->ng;
    w->ax = q, q += w->k;
    w->ap = q, q += np;
    w->aJ = q, q += (size_t)w->k * w->k;
    w->scale = q, q += np;
    w->P = q, q += np;
    w->gp = q, q += w->ng;
    w->xp = q, q += w->k;
    w->xver = q, q += w->k;
    w->vver = q;
    o.tip_only = 1;
    w->d = tr_data_alloc(w->m, &o, 1, NULL, msg, msglen);
    return w->d ? TR_OK : TR_ENOMEM;
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

/* The scale of each varied value, in gather's order: a displacement by the tendon's
 * largest offset (L if none), a tension and a force by EI/L^2, a moment by EI/L, the
 * distributed force by EI/L^3. */
static void scales(const tr_model *m, const tr_batch_in *in, double *S)
{
    int o = 0, i;
    if (in->value)
        for (i = 0; i < m->nt; i++) {
            const tr_tendon *t = m->tendon + i;
            const double r = fmax(fabs(t->b), fabs(t->b + t->a * t->t));
            S[o++] = t->control == TR_DISPLACEMENT ? (r > 0.0 ? r : m->L) : m->F_s;
        }
    if (in->load)
        for (i = 0; i < 6 * m->nl; i++) S[o++] = i % 6 < 3 ? m->F_s : m->M_s;
    if (in->dist)
        for (i = 0; i < 3; i++) S[o++] = m->F_s / m->L;
}

/* Scaled distance squared between two points' varied values. */
static double dist2(const double *a, const double *b, const double *S, int np)
{
    double s = 0.0;
    int i;
    for (i = 0; i < np; i++) s += (a[i] - b[i]) * (a[i] - b[i]) / (S[i] * S[i]);
    return s;
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
    const double *P = w->P, *P1 = w->hist_p[0], *P0 = w->hist_p[1], *P00 = w->hist_p[2];
    const double *P000 = w->hist_p[3];
    const double c = have >= 2 ? collinear(P, P1, P1, P0, w->np) : 0.0;
    double c2 = 0.0;
    wt[3] = 0.0;
    if (c == 0.0) return 0;
    if (have >= 3) c2 = collinear(P1, P0, P0, P00, w->np);
    if (have >= 4 && fabs(c - 1.0) <= 1e-9 && fabs(c2 - 1.0) <= 1e-9 &&
        fabs(collinear(P0, P00, P00, P000, w->np) - 1.0) <= 1e-9) {
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

static void extrapolate(const double wt[4], double *const hist[TR_BATCH_HIST], double *out, int n)
{
    int i;
    for (i = 0; i < n; i++)
        out[i] = wt[0] * hist[0][i] + wt[1] * hist[1][i] +
                 (wt[2] != 0.0 ? wt[2] * hist[2][i] : 0.0) +
                 (wt[3] != 0.0 ? wt[3] * hist[3][i] : 0.0);
}

/* A converged point becomes the newest of the history (the oldest buffer is reused);
 * have: the points on record after it.  Where it starts a new line (it is not on the
 * line through the two before it), the point before it -- the first of that line --
 * becomes the anchor. */
static void push_converged(batch_ws *w, const tr_model *m, const tr_data *d, int have)
{
    double *g = w->hist_g[TR_BATCH_HIST - 1], *x = w->hist_x[TR_BATCH_HIST - 1];
    double *p = w->hist_p[TR_BATCH_HIST - 1], *J = w->hist_J[TR_BATCH_HIST - 1];
    const size_t kk = (size_t)w->k * w->k;
    int h;
    for (h = TR_BATCH_HIST - 1; h > 0; h--) {
        w->hist_g[h] = w->hist_g[h - 1];
        w->hist_x[h] = w->hist_x[h - 1];
        w->hist_p[h] = w->hist_p[h - 1];
        w->hist_J[h] = w->hist_J[h - 1];
    }
    w->hist_g[0] = g;
    w->hist_x[0] = x;
    w->hist_p[0] = p;
    w->hist_J[0] = J;
    tr_base_state(m, d, g);
    memcpy(x, d->x, (size_t)w->k * sizeof(double));
    memcpy(p, w->P, (size_t)w->np * sizeof(double));
    memcpy(J, d->J, kk * sizeof(double));
    if (have >= 3 && collinear(p, w->hist_p[1], w->hist_p[1], w->hist_p[2], w->np) != 0.0) {
        w->run++;
    } else {
        w->run = have >= 2 ? 2 : 1;
        if (have >= 2) {
            memcpy(w->ag, w->hist_g[1], (size_t)w->ng * sizeof(double));
            memcpy(w->ax, w->hist_x[1], (size_t)w->k * sizeof(double));
            memcpy(w->ap, w->hist_p[1], (size_t)w->np * sizeof(double));
            memcpy(w->aJ, w->hist_J[1], kk * sizeof(double));
            w->have_anchor = 1;
        }
    }
    w->ver.steps = d->have_ver ? d->steps_ver : 0;
    w->ver.estimate = d->est_ver;
    w->ver.x = w->xver;
    if (d->have_ver) memcpy(w->xver, d->x_ver, (size_t)w->k * sizeof(double));
    w->ver.values = d->have_val_ver ? w->vver : NULL;
    if (d->have_val_ver) memcpy(w->vver, d->val_ver, (size_t)m->nt * sizeof(double));
}

static void write_failed_point(const tr_batch_out *out, int p, int nt, int k, int st,
                               const char *pmsg)
{
    int i;
    for (i = 0; i < 3; i++) out->tip_pos[3 * p + i] = NAN;
    for (i = 0; i < 9; i++) out->tip_rot[9 * p + i] = NAN;
    for (i = 0; i < nt; i++)
        out->tension[nt * p + i] = out->slack[nt * p + i] = out->displacement[nt * p + i] = NAN;
    out->residual[p] = NAN;
    out->status[p] = st;
    out->nit[p] = out->nfev[p] = 0;
    if (out->cold) out->cold[p] = 1;
    if (out->stable) out->stable[p] = -1;
    if (out->message) tr_msgf(out->message + (size_t)p * out->msglen, out->msglen, "%s", pmsg);
    if (out->unknowns)
        for (i = 0; i < k; i++) out->unknowns[(size_t)k * p + i] = NAN;
    if (out->steps) out->steps[p] = 0;
}

static void write_point(const tr_batch_out *out, int p, const tr_model *m, const tr_data *d, int st,
                        int nit, int nfev, int cold)
{
    const int nt = m->nt;
    memcpy(out->tip_pos + 3 * p, d->pos, 3 * sizeof(double));
    memcpy(out->tip_rot + 9 * p, d->rot, 9 * sizeof(double));
    if (nt > 0) {
        memcpy(out->tension + (size_t)nt * p, d->tension, (size_t)nt * sizeof(double));
        memcpy(out->slack + (size_t)nt * p, d->slack, (size_t)nt * sizeof(double));
        memcpy(out->displacement + (size_t)nt * p, d->displacement, (size_t)nt * sizeof(double));
    }
    out->residual[p] = d->residual_norm;
    out->status[p] = st;
    if (out->stable) out->stable[p] = st >= 0 ? d->stable : -1;
    out->nit[p] = nit;
    out->nfev[p] = nfev;
    if (out->cold) out->cold[p] = cold;
    if (st != TR_OK && out->message)
        tr_msgf(out->message + (size_t)p * out->msglen, out->msglen, "%s", d->message);
    if (out->unknowns)
        memcpy(out->unknowns + (size_t)d->k * p, d->x, (size_t)d->k * sizeof(double));
    if (out->steps) out->steps[p] = d->opt.integrator == TR_ADAPTIVE ? 0 : d->steps;
}

/* Solve one point whose values are set: lean first where it applies, then tr_solve,
 * then (optionally) tr_solve cold.  Counts go into *nit, *nfev; *cold says whether
 * the returned solve had no guess. */
static int solve_point(batch_ws *w, const tr_batch_in *in, int have, int record, int *nit,
                       int *nfev, int *cold)
{
    const tr_model *m = w->m;
    tr_data *d = w->d;
    const double *g = w->hist_g[0], *J = w->hist_J[0];
    const tr_verified *ver = w->ver.steps > 0 ? &w->ver : NULL;
    double wt[4], spent = 0.0;
    int st = TR_EINVAL, order = 0;
    *cold = !(in->warm && have);
    *nit = *nfev = 0;
    if (have >= 1) memcpy(w->xp, w->hist_x[0], (size_t)w->k * sizeof(double));
    if (!*cold && !in->exact && in->predict) {
        if (have >= 2) order = predict_weights(w, have, wt);
        if (order > 0) {
            extrapolate(wt, w->hist_g, w->gp, w->ng);
            extrapolate(wt, w->hist_x, w->xp, w->k);
            g = w->gp;
        } else if (w->have_anchor && dist2(w->P, w->ap, w->scale, w->np) <
                                         dist2(w->P, w->hist_p[0], w->scale, w->np)) {
            memcpy(w->xp, w->ax, (size_t)w->k * sizeof(double));
            g = w->ag;
            J = w->aJ;
            ver = NULL;
        }
    }
    if (!*cold && !in->exact && d->opt.steps > 0 && d->opt.integrator != TR_ADAPTIVE) {
        const int iters = d->opt.max_iter < TR_LEAN_ITER ? d->opt.max_iter : TR_LEAN_ITER;
        st = tr_solve_lean(m, d, w->xp, J, iters);
        /* an unstable answer goes to the full solve, which looks for a stable one */
        if (st == TR_OK && !tr_branch_lean(m, d)) st = TR_ENOPROGRESS;
        if (st == TR_OK) st = record ? tr_record(m, d) : tr_record_tip(m, d);
        *nit = d->nit;
        *nfev = d->nfev;
        spent = d->spent;
        /* an interrupt during the lean solve's verdict or recording stops the point too
         * (the full solve would start a new poll and lose it) */
        if (d->stop == TR_EINTERRUPTED) return TR_EINTERRUPTED;
        if (st == TR_OK) return st;
    }
    if (*cold)
        st = tr_solve(m, d, NULL, NULL);
    else
        st = tr_solve_from(m, d, g, J, ver);
    *nit += d->nit;
    *nfev += d->nfev;
    spent += d->spent;
    /* a point has one work budget: the cold retry gets what the warm tries left */
    if (st < 0 && st != TR_EINTERRUPTED && st != TR_EBUDGET && !*cold && in->retry_cold &&
        spent < d->opt.max_work) {
        const double budget = d->opt.max_work;
        d->opt.max_work = budget - spent;
        st = tr_solve(m, d, NULL, NULL);
        d->opt.max_work = budget;
        *nit += d->nit;
        *nfev += d->nfev;
        *cold = 1;
    }
    return st;
}

static int check_args(const tr_model *m, const tr_options *opt, const tr_batch_in *in,
                      const tr_batch_out *out, char *msg, size_t msglen)
{
    if (!m || !opt || !in || !out) {
        tr_msgf(msg, msglen, "tr_batch_solve: NULL argument");
        return TR_EINVAL;
    }
    if (in->n < 0) {
        tr_msgf(msg, msglen, "tr_batch_solve: n = %d must be >= 0", in->n);
        return TR_EINVAL;
    }
    if (!out->tip_pos || !out->tip_rot || !out->residual || !out->status || !out->nit ||
        !out->nfev || (m->nt > 0 && (!out->tension || !out->slack || !out->displacement))) {
        tr_msgf(msg, msglen, "tr_batch_solve: an output array is NULL");
        return TR_EINVAL;
    }
    return TR_OK;
}

int tr_batch_solve(const tr_model *m, const tr_options *opt, const tr_batch_in *in,
                   tr_batch_out *out, char *msg, size_t msglen)
{
    batch_ws w;
    int p, i, have = 0, record, nten = 0, st;
    const int np =
        (in && in->value ? m->nt : 0) + (in && in->load ? 6 * m->nl : 0) + (in && in->dist ? 3 : 0);
    st = check_args(m, opt, in, out, msg, msglen);
    if (st != TR_OK || in->n == 0) return st;
    st = ws_alloc(&w, m, opt, np, msg, msglen);
    if (st != TR_OK) {
        ws_free(&w);
        return st;
    }
    /* the recording pass adds nothing unless a tension-controlled tendon's
     * displacement is wanted */
    for (i = 0; i < m->nt; i++) nten += m->tendon[i].control == TR_TENSION;
    record = nten > 0 && !in->skip_tension_displacement;
    scales(m, in, w.scale);
    tr_set_poll(w.d, in->poll, in->poll_ctx);
    for (p = 0; p < in->n; p++) {
        char pmsg[TR_MSGLEN];
        int nit, nfev, cold;
        const double *v = in->value ? in->value + (size_t)p * m->nt : NULL;
        const double *l = in->load ? in->load + (size_t)p * 6 * m->nl : NULL;
        const double *dd = in->dist ? in->dist + (size_t)p * 3 : NULL;
        if (tr_data_set_values(w.m, w.d, v, l, dd, pmsg, sizeof pmsg) != TR_OK) {
            char full[TR_MSGLEN + 32];
            tr_msgf(full, sizeof full, "point %d: %s", p, pmsg);
            write_failed_point(out, p, m->nt, m->n_unknowns, TR_EINVAL, full);
            continue;
        }
        gather(m, in, p, w.P);
        st = solve_point(&w, in, have, record, &nit, &nfev, &cold);
        if (st == TR_EINTERRUPTED) {
            /* this point and the rest are not solved */
            for (; p < in->n; p++)
                write_failed_point(out, p, m->nt, m->n_unknowns, TR_EINTERRUPTED,
                                   "interrupted by the caller");
            ws_free(&w);
            return TR_EINTERRUPTED;
        }
        write_point(out, p, w.m, w.d, st, nit, nfev, cold);
        if (TR_SUCCEEDED(st)) {
            have = have < TR_BATCH_HIST ? have + 1 : TR_BATCH_HIST;
            push_converged(&w, w.m, w.d, have);
        } else {
            have = have > 0 ? 1 : 0; /* no extrapolation across a failed point */
        }
    }
    ws_free(&w);
    return TR_OK;
}
