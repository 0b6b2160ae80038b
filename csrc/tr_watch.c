/*
 * tr_watch.c -- does a tendon approach the centre of curvature?
 *
 * A taut tendon at offset r from the centre line has the path-length rate
 * w = v + u x r + r'; where the backbone bends toward it with curvature 1/r
 * (tension near EI / r^2 at a moment-free end) w vanishes and the tendon would pass
 * the centre of curvature (past it w points backwards): the model has no equilibrium
 * there.  When a load path stalls, the state it stalled on is walked along s and the
 * smallest rate w . w_ref / |w_ref|^2 of a taut tendon is kept with its tendon, arc
 * length, tension and the limit EI / r^2, so that the failure can name them even when
 * the stall happens below the limit; a converged state whose verification failed is
 * walked the same way (a state past the limit is no answer).
 */
#include <math.h>
#include <stdio.h>

#include "tendonrod.h"
#include "tr_internal.h"
#include "tru_math.h"

/* The path-length rate of tendon i at s on state y (shooting layout, segment d->seg),
 * w = v + u x r + r' against the unstressed robot's w_ref: signed, w . w_ref / |w_ref|^2
 * (1 in the unstressed robot, 0 where the tendon reaches the centre of curvature, negative
 * past it, where its path runs backwards: for converged states), or |w| / |w_ref| (for the
 * iterates a load path stalled on, which may be far from any equilibrium); its offset |r|
 * into *rr. */
static double rate_of(const tr_model *m, const tr_data *d, int i, double s, const double *y,
                      int sign, double *rr)
{
    const double *sr = m->seg_rod + TR_SR_NCOL * d->seg;
    double r[3], rp[3], u[3], v[3] = {0, 0, 1}, w[3], wr[3];
    int c;
    tr_tendon_offset(m, i, d->seg, s, r, rp);
    for (c = 0; c < 3; c++) u[c] = sr[TR_SR_U + c];
    if (m->planar) {
        u[1] += y[TR_YP_M] / sr[TR_SR_EI];
        if (!m->kirchhoff) {
            v[0] = y[TR_YP_N1] / sr[TR_SR_GA];
            v[2] = 1.0 + y[TR_YP_N3] / sr[TR_SR_EA];
        }
    } else {
        const double *nb = y + TR_Y_N, *mb = y + TR_Y_M;
        u[0] += mb[0] / sr[TR_SR_EI];
        u[1] += mb[1] / sr[TR_SR_EI];
        u[2] += mb[2] / sr[TR_SR_GJ];
        if (!m->kirchhoff) {
            v[0] = nb[0] / sr[TR_SR_GA];
            v[1] = nb[1] / sr[TR_SR_GA];
            v[2] = 1.0 + nb[2] / sr[TR_SR_EA];
        }
    }
    tru_cross3(w, u, r);
    for (c = 0; c < 3; c++) w[c] += v[c] + rp[c];
    tr_tendon_wref(m, i, d->seg, s, wr);
    *rr = tru_norm3(r);
    return sign ? tru_dot3(w, wr) / tru_dot3(wr, wr) : tru_norm3(w) / tru_norm3(wr);
}

/* the smallest rate of the taut tendons active on segment k at s; updates *best, and *bt
 * the tension there (with friction, the local one) */
static void check_at(const tr_model *m, const tr_data *d, int k, double s, const double *y,
                     int sign, double *best, int *bi, double *bs, double *br, double *bt)
{
    int c;
    for (c = m->seg_act_start[k]; c < m->seg_act_start[k + 1]; c++) {
        const int i = m->seg_act[c];
        const double tau = tr_tension_at(m, d, i, y);
        double rr, rate;
        if (!(tau > 0.0)) continue;
        rate = rate_of(m, d, i, s, y, sign, &rr);
        if (rate < *best && rr > 0.0) {
            *best = rate;
            *bi = i;
            *bs = s;
            *bt = tau;
            /* the limit EI / r^2 with the segment's EI: kept as r / sqrt(EI / EI_rod) */
            *br = rr * sqrt(m->EI / m->seg_rod[TR_SR_NCOL * k + TR_SR_EI]);
        }
    }
}

double tr_watch_curvature(const tr_model *m_, tr_data *d, const double *x, int keep)
{
    const tr_model *m = TR_IN(m_, d);
    double *y = d->y, best = INFINITY, bs = NAN, br = NAN, bt = NAN;
    int k, j, c, bi = -1;
    if (m->nt == 0 || d->k == 0) return NAN;
    d->rec = 0;
    d->nfev++;
    d->y_steps = -1;
    tr_set_tensions(m, d, x);
    tr_init_state(m, d, x, y, m->n_states);
    for (k = 0; k < m->nseg; k++) {
        const double s0 = m->bp[k], s1 = m->bp[k + 1];
        int n = tr_segment_steps(m, d, k);
        const int nmin = (int)ceil(TR_WATCH_STEPS * (s1 - s0) / m->L);
        if (n < nmin) n = nmin;
        d->seg = k;
        check_at(m, d, k, s0, y, keep == 2, &best, &bi, &bs, &br, &bt);
        for (j = 0; j < n; j++) {
            const double sa = s0 + (s1 - s0) * j / n, sb = s0 + (s1 - s0) * (j + 1) / n;
            if (tr_integrate(m, d, sa, sb, 1, y) != TR_OK) return NAN;
            check_at(m, d, k, sb, y, keep == 2, &best, &bi, &bs, &br, &bt);
        }
        if (k + 1 < m->nseg) {
            tr_apply_jump(m, d, k + 1, y);
            if (m->bp_node[k + 1] > 0) {
                const int o = tr_node_off(m, m->bp_node[k + 1]);
                for (c = 0; c < m->n_states; c++) y[c] = x[o + c] * tr_node_scale(m, c);
            }
        }
    }
    if (bi < 0) return NAN;
    if (keep == 2 || (keep == 1 && (!d->watch_have || best < d->watch_rate))) {
        d->watch_have = 1;
        d->watch_rate = best;
        d->watch_tendon = bi;
        d->watch_s = bs;
        d->watch_tau = bt;
        d->watch_limit = m->EI / (br * br);
        d->watch_act = d->lam_act;
        d->watch_load = d->lam_load;
    }
    return best;
}

/* The named reason from d->watch_*, the state placed by `where`; 0 if the kept rate is
 * not below TR_WATCH_RATE. */
static int watch_format(const tr_data *d, const char *where, char *buf, size_t len)
{
    if (!d->watch_have || !(d->watch_rate < TR_WATCH_RATE)) return 0;
    snprintf(buf, len,
             "tendon %d would pass the centre of curvature: %s its "
             "path-length rate |w| fell to %.3g of the straight robot's "
             "at s = %.4g m, with tension %.4g N against the limit EI/r^2 = %.4g N there (the "
             "backbone curvature approaches 1/r); the model has no equilibrium past that "
             "point on this path (reduce the load or the actuation, or route the tendon "
             "closer to the centre line)",
             d->watch_tendon, where, d->watch_rate, d->watch_s, d->watch_tau, d->watch_limit);
    return 1;
}

int tr_watch_message(const tr_model *m_, const tr_data *d, char *buf, size_t len)
{
    const tr_model *m = TR_IN(m_, d);
    char where[128];
    (void)m;
    if (d->watch_act < 1.0)
        snprintf(where, sizeof where, "where the solve stalled (at %.4g of the actuation)",
                 d->watch_act);
    else if (d->watch_load < 1.0)
        snprintf(where, sizeof where, "where the solve stalled (at %.4g of the loads)",
                 d->watch_load);
    else
        snprintf(where, sizeof where, "where the solve stalled (at the full loads)");
    return watch_format(d, where, buf, len);
}

int tr_watch_named(const tr_model *m_, tr_data *d, const double *x, const char *where, char *buf,
                   size_t len)
{
    const tr_model *m = TR_IN(m_, d);
    d->watch_have = 0;
    d->lam_act = d->lam_load = 1.0;
    tr_watch_curvature(m, d, x, 2);
    return watch_format(d, where, buf, len);
}
