/*
 * tr_model.c -- compile a scene into the smallest problem that represents it.
 *
 * Validation (every value, with a message naming it), breakpoints (tendon
 * anchors and point loads inside (0, L)), the active-tendon lists per segment,
 * the formulation (planar or spatial; unknowns; path-length states only for
 * displacement-controlled tendons), scales, tendon rest lengths (pretension),
 * and the compile-time checks for statically indeterminate or impossible
 * inextensible tendon sets on an inextensible backbone.
 */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tendonrod.h"
#include "tr_internal.h"

/* Breakpoints closer than this fraction of L are merged (round-off in user
 * arc lengths such as 0.1 * 3 vs 0.3). */
#define TR_BP_MERGE 1e-12
/* |sin phi| below this counts as in-plane (phi = 0 or pi given in floating point). */
#define TR_PLANAR_SIN 1e-12
/* Relative tolerance of the pretension balance check sum(tau_p r_i) = 0. */
#define TR_BALANCE_TOL 1e-9

tr_options tr_default_options(void)
{
    tr_options o;
    o.integrator = TR_RK8;
    o.steps = 0;
    o.rtol = 1e-10;
    o.tol = 1e-10;
    o.max_iter = 50;
    o.max_nfev = 20000;
    o.jacobian_method = TR_JAC_FD;
    o.slack_model = TR_SLACK_LINEAR;
    o.continuation = 1;
    o.max_continuation = 64;
    o.force_spatial = 0;
    o.tip_only = 0;
    o.shooting_segments = 1;
    return o;
}

static void msgf(char *msg, size_t len, const char *fmt, ...)
{
    va_list ap;
    if (!msg || len == 0) return;
    va_start(ap, fmt);
    vsnprintf(msg, len, fmt, ap);
    va_end(ap);
}

void tr_model_free(tr_model *m)
{
    if (!m) return;
    free(m->tendon);
    free(m->load);
    free(m->bp);
    free(m->bpF);
    free(m->bpM);
    free(m->seg_act_start);
    free(m->seg_act);
    free(m->bp_node);
    free(m->bp_jump);
    free(m);
}

static int cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static int find_bp(const tr_model *m, double s)
{
    int k, best = 0;
    double dmin = INFINITY;
    for (k = 0; k <= m->nseg; k++) {
        const double dd = fabs(m->bp[k] - s);
        if (dd < dmin) {
            dmin = dd;
            best = k;
        }
    }
    return best;
}

/* Pretension: rest lengths so that each tendon holds its pretension at q = 0 in
 * the straight robot, uniformly compressed by the pretensions if Cosserat. */
static int set_rest_lengths(tr_model *m, char *msg, size_t msglen)
{
    int i, k, any = 0;
    for (i = 0; i < m->nt; i++) {
        tr_tendon *t = &m->tendon[i];
        t->sref = t->t * sqrt(1.0 + t->a * t->a);
        t->rest = t->sref;
        t->rest_dev = 0.0;
        if (t->pretension != 0.0) any = 1;
    }
    if (!any) return TR_OK;
    /* balance on every segment (checked at both ends: r is linear in s) */
    for (k = 0; k < m->nseg; k++) {
        int e;
        for (e = 0; e < 2; e++) {
            const double s = m->bp[k + e];
            double sx = 0.0, sy = 0.0, mag = 0.0;
            int c;
            for (c = m->seg_act_start[k]; c < m->seg_act_start[k + 1]; c++) {
                const tr_tendon *t = &m->tendon[m->seg_act[c]];
                const double rho = t->a * s + t->b;
                sx += t->pretension * rho * t->cphi;
                sy += t->pretension * rho * t->sphi;
                mag += fabs(t->pretension * rho);
            }
            if (hypot(sx, sy) > TR_BALANCE_TOL * mag + 1e-300) {
                msgf(msg, msglen,
                     "pretension is not balanced: sum of pretension*r(s) = (%.6g, %.6g) N m at "
                     "s = %.6g m; pretension is only meaningful for a balanced set of tendons "
                     "(e.g. equal pretension on equally spaced tendons)",
                     sx, sy, s);
                return TR_EPRETENSION;
            }
        }
    }
    {
        int compliant = !m->kirchhoff;
        for (i = 0; i < m->nt; i++) {
            const tr_tendon *t = &m->tendon[i];
            if (t->pretension != 0.0 && isfinite(t->EA)) compliant = 1;
        }
        if (!compliant) {
            msgf(msg, msglen,
                 "pretension needs axial compliance: the pretensioned tendons are inextensible "
                 "(EA = inf) and the backbone is inextensible (kirchhoff), so no rest length "
                 "gives a finite pretension; give the tendons a finite EA or the backbone an "
                 "extension stiffness");
            return TR_EPRETENSION;
        }
    }
    for (i = 0; i < m->nt; i++) {
        tr_tendon *t = &m->tendon[i];
        double len = 0.0;
        if (t->pretension < 0.0) {
            msgf(msg, msglen, "tendon %d: pretension = %g N must be >= 0 (a tendon cannot push)", i,
                 t->pretension);
            return TR_EINVAL;
        }
        /* len - sref accumulated without cancellation: per segment
         * sqrt(a^2 + v3^2) - c = (v3^2 - 1) / (sqrt(a^2 + v3^2) + c), v3^2 - 1 = e (2 + e) */
        for (k = 0; k < t->end_bp; k++) {
            double e = 0.0; /* v3 - 1 */
            const double c = sqrt(1.0 + t->a * t->a);
            if (!m->kirchhoff) {
                /* straight state: n3 = -sum tau_p v3 / |w|, |w| = sqrt(a^2 + v3^2);
                 * fixed point in e = v3 - 1 (contracting: tau_p / EA << 1) */
                int it;
                for (it = 0; it < 60; it++) {
                    double n3 = 0.0, en;
                    int cc;
                    for (cc = m->seg_act_start[k]; cc < m->seg_act_start[k + 1]; cc++) {
                        const tr_tendon *tc = &m->tendon[m->seg_act[cc]];
                        n3 -= tc->pretension * (1.0 + e) /
                              sqrt(tc->a * tc->a + (1.0 + e) * (1.0 + e));
                    }
                    en = n3 / m->EA;
                    if (fabs(en - e) <= 1e-18) {
                        e = en;
                        break;
                    }
                    e = en;
                }
            }
            len += (m->bp[k + 1] - m->bp[k]) * e * (2.0 + e) /
                   (sqrt(t->a * t->a + (1.0 + e) * (1.0 + e)) + c);
        }
        /* rest = (sref + len) / (1 + tau_p/EA);  rest - sref = (len - sref tau_p/EA) / (1 + tau_p/EA) */
        {
            const double st = isfinite(t->EA) ? t->pretension / t->EA : 0.0;
            t->rest_dev = (len - t->sref * st) / (1.0 + st);
            t->rest = t->sref + t->rest_dev;
        }
    }
    return TR_OK;
}

/* Inextensible displacement-controlled tendons on a Kirchhoff backbone: a
 * positive combination c with sum c_i r_i(s) = 0 keeps sum c_i s_i >= sum c_i s_ref,i,
 * so sum c_i q_i > 0 has no equilibrium and sum c_i q_i = 0 leaves the common
 * tension level free.  Pairs and triples anchored at the same place are checked. */
static int check_indeterminate(const tr_model *m, char *msg, size_t msglen)
{
    int i, j, l, n = 0;
    int idx[64];
    if (!m->kirchhoff) return TR_OK;
    for (i = 0; i < m->nt && n < 64; i++) {
        const tr_tendon *t = &m->tendon[i];
        if (t->control == TR_DISPLACEMENT && !isfinite(t->EA)) idx[n++] = i;
    }
    for (i = 0; i < n; i++)
        for (j = i + 1; j < n; j++) {
            const tr_tendon *ti = &m->tendon[idx[i]], *tj = &m->tendon[idx[j]];
            const double gi[4] = {ti->b * ti->cphi, ti->b * ti->sphi, ti->a * ti->cphi,
                                  ti->a * ti->sphi};
            const double gj[4] = {tj->b * tj->cphi, tj->b * tj->sphi, tj->a * tj->cphi,
                                  tj->a * tj->sphi};
            double gg = 0, gij = 0, ni = 0, res = 0, mu, ncomb;
            int q;
            double c[3] = {1.0, 0.0, 0.0};
            int found = 0, third = -1;
            if (ti->end_bp != tj->end_bp) continue;
            for (q = 0; q < 4; q++) {
                gg += gj[q] * gj[q];
                gij += gi[q] * gj[q];
                ni += gi[q] * gi[q];
            }
            if (gg > 0.0) {
                mu = -gij / gg;
                for (q = 0; q < 4; q++) res += (gi[q] + mu * gj[q]) * (gi[q] + mu * gj[q]);
                if (mu > 0.0 && res <= 1e-20 * ni) {
                    found = 1;
                    c[1] = mu;
                }
            }
            for (l = j + 1; l < n && !found; l++) {
                /* gi + c1 gj + c2 gl = 0 with c1, c2 > 0 (least squares, 2x2 normal eqs) */
                const tr_tendon *tl = &m->tendon[idx[l]];
                const double gl[4] = {tl->b * tl->cphi, tl->b * tl->sphi, tl->a * tl->cphi,
                                      tl->a * tl->sphi};
                double a11 = 0, a12 = 0, a22 = 0, r1 = 0, r2 = 0, det, c1, c2, rr = 0;
                if (tl->end_bp != ti->end_bp) continue;
                for (q = 0; q < 4; q++) {
                    a11 += gj[q] * gj[q];
                    a12 += gj[q] * gl[q];
                    a22 += gl[q] * gl[q];
                    r1 -= gj[q] * gi[q];
                    r2 -= gl[q] * gi[q];
                }
                det = a11 * a22 - a12 * a12;
                if (!(fabs(det) > 1e-30 * (a11 * a22 + 1e-300))) continue;
                c1 = (a22 * r1 - a12 * r2) / det;
                c2 = (a11 * r2 - a12 * r1) / det;
                for (q = 0; q < 4; q++) {
                    const double e = gi[q] + c1 * gj[q] + c2 * gl[q];
                    rr += e * e;
                }
                if (c1 > 0.0 && c2 > 0.0 && rr <= 1e-20 * ni) {
                    found = 1;
                    c[1] = c1;
                    c[2] = c2;
                    third = l;
                }
            }
            if (!found) continue;
            {
                double Q = c[0] * ti->value + c[1] * tj->value, csum = c[0] + c[1];
                char names[64];
                if (third >= 0) {
                    Q += c[2] * m->tendon[idx[third]].value;
                    csum += c[2];
                    snprintf(names, sizeof names, "tendons %d, %d, %d", idx[i], idx[j], idx[third]);
                } else {
                    snprintf(names, sizeof names, "tendons %d and %d", idx[i], idx[j]);
                }
                ncomb = 1e-13 * m->L * csum;
                if (Q > ncomb) {
                    msgf(msg, msglen,
                         "no equilibrium: %s are opposing inextensible tendons on an inextensible "
                         "backbone and their displacements retract them together (weighted sum "
                         "%.6g m > 0), which would need the backbone to shorten; release one of "
                         "them, or give the tendons a finite EA or the backbone an extension "
                         "stiffness",
                         names, Q / csum);
                    return TR_ENOEQUILIBRIUM;
                }
                if (Q >= -ncomb) {
                    msgf(msg, msglen,
                         "statically indeterminate: opposing inextensible tendons on an "
                         "inextensible backbone (%s; their common tension level is free); give "
                         "the tendons a finite EA or the backbone an extension stiffness",
                         names);
                    return TR_EINDETERMINATE;
                }
            }
        }
    return TR_OK;
}

int tr_model_alloc(tr_model **out, const double rod[6], const double *tendons, int nt,
                   const double *loads, int nl, const double dist[3], const tr_options *opt,
                   char *msg, size_t msglen)
{
    tr_model *m = NULL;
    double *cand = NULL;
    int i, k, nc = 0, status = TR_OK, ndisp = 0;
    double rmax = 0.0;

    *out = NULL;
    if (msg && msglen) msg[0] = '\0';
    if (nt < 0 || nl < 0 || (nt > 0 && !tendons) || (nl > 0 && !loads) || !rod || !dist || !opt) {
        msgf(msg, msglen, "invalid arguments to tr_model_alloc (negative count or NULL array)");
        return TR_EINVAL;
    }
    {
        const char *names[6] = {"rod length L", "rod EI", "rod GJ",
                                "rod EA",       "rod GA", "rod kirchhoff"};
        for (i = 0; i < 5; i++) {
            /* EA, GA may be inf for a Kirchhoff rod only */
            const int may_inf = (i >= 3 && rod[5] != 0.0);
            if (!(rod[i] > 0.0) || (!may_inf && !isfinite(rod[i]))) {
                msgf(msg, msglen, "%s = %g must be finite and > 0", names[i], rod[i]);
                return TR_EINVAL;
            }
        }
        /* scales EI/L^2, EI/L and the stiffness ratios must stay normal doubles */
        if (rod[0] > 1e100 || rod[0] < 1e-100 || rod[1] > 1e100 || rod[1] < 1e-100 ||
            rod[2] > 1e100 || rod[2] < 1e-100 ||
            (isfinite(rod[3]) && (rod[3] > 1e150 || rod[3] < 1e-100)) ||
            (isfinite(rod[4]) && (rod[4] > 1e150 || rod[4] < 1e-100))) {
            msgf(msg, msglen,
                 "rod values out of range: L = %g m, EI = %g, GJ = %g N m^2, EA = %g, GA = %g N "
                 "(L, EI, GJ within [1e-100, 1e100]; EA, GA within [1e-100, 1e150] or inf for a "
                 "Kirchhoff rod)",
                 rod[0], rod[1], rod[2], rod[3], rod[4]);
            return TR_EINVAL;
        }
        if (rod[5] != 0.0 && rod[5] != 1.0) {
            msgf(msg, msglen, "%s = %g must be 0 or 1", names[5], rod[5]);
            return TR_EINVAL;
        }
    }
    for (i = 0; i < 3; i++)
        if (!isfinite(dist[i])) {
            msgf(msg, msglen, "dist[%d] = %g must be finite", i, dist[i]);
            return TR_EINVAL;
        }

    m = (tr_model *)calloc(1, sizeof *m);
    if (!m) {
        status = TR_ENOMEM;
        goto fail;
    }
    m->L = rod[0];
    m->EI = rod[1];
    m->GJ = rod[2];
    m->EA = rod[3];
    m->GA = rod[4];
    m->kirchhoff = rod[5] != 0.0;
    m->nt = nt;
    m->nl = nl;
    m->tendon = (tr_tendon *)calloc(nt > 0 ? nt : 1, sizeof(tr_tendon));
    m->load = (double *)calloc(nl > 0 ? 7 * nl : 1, sizeof(double));
    if (!m->tendon || !m->load) {
        status = TR_ENOMEM;
        goto fail;
    }

    for (i = 0; i < nt; i++) {
        const double *row = tendons + 8 * i;
        tr_tendon *t = &m->tendon[i];
        static const char *col[8] = {"offset", "angle",   "slope", "EA",
                                     "end",    "control", "value", "pretension"};
        int c;
        for (c = 0; c < 8; c++)
            if (isnan(row[c]) || (c != 3 && !isfinite(row[c]))) {
                msgf(msg, msglen, "tendons[%d] %s = %g must be finite", i, col[c], row[c]);
                status = TR_EINVAL;
                goto fail;
            }
        t->b = row[0];
        t->phi = row[1];
        t->a = row[2];
        t->EA = row[3];
        t->t = row[4];
        t->value = row[6];
        t->pretension = row[7]; /* control: set once validated below */
        if (!(t->EA > 0.0) ||
            (isfinite(t->EA) && (t->EA < TR_TENDON_EA_MIN || t->EA > TR_TENDON_EA_MAX))) {
            msgf(msg, msglen,
                 "tendons[%d] EA = %g must lie in [%g, %g] N, or be inf (inextensible)", i, t->EA,
                 TR_TENDON_EA_MIN, TR_TENDON_EA_MAX);
            status = TR_EINVAL;
            goto fail;
        }
        if (!(t->t > 0.0) || t->t > m->L * (1.0 + TR_BP_MERGE)) {
            msgf(msg, msglen, "tendons[%d] end = %g m must lie in (0, L = %g]", i, t->t, m->L);
            status = TR_EINVAL;
            goto fail;
        }
        if (t->t > m->L) t->t = m->L;
        /* compared as a double first: converting an out-of-range double to int is
         * undefined behaviour (finding F17) */
        if (row[5] != 0.0 && row[5] != 1.0) {
            msgf(msg, msglen, "tendons[%d] control = %g must be 0 (displacement) or 1 (tension)", i,
                 row[5]);
            status = TR_EINVAL;
            goto fail;
        }
        t->control = row[5] == 1.0 ? TR_TENSION : TR_DISPLACEMENT;
        if (t->control == TR_TENSION && t->value < 0.0) {
            msgf(msg, msglen, "tendons[%d] tension = %g N must be >= 0 (a tendon cannot push)", i,
                 t->value);
            status = TR_EINVAL;
            goto fail;
        }
        if (t->pretension < 0.0) {
            msgf(msg, msglen, "tendons[%d] pretension = %g N must be >= 0", i, t->pretension);
            status = TR_EINVAL;
            goto fail;
        }
        {
            const double rb = fabs(t->b), re = fabs(t->a * t->t + t->b);
            if (t->control == TR_DISPLACEMENT) {
                if (rb > rmax) rmax = rb;
                if (re > rmax) rmax = re;
            }
        }
        t->cphi = cos(t->phi);
        t->sphi = sin(t->phi);
        {
            const double h = sqrt(1.0 + t->a * t->a);
            t->t0[0] = t->a * t->cphi / h;
            t->t0[1] = t->a * t->sphi / h;
            t->t0[2] = 1.0 / h;
            t->rt0[0] = t->b * t->sphi / h;
            t->rt0[1] = -t->b * t->cphi / h;
            t->rt0[2] = 0.0;
        }
        if (t->control == TR_DISPLACEMENT) {
            t->gamma_index = ndisp;
            t->len_index = ndisp;
            ndisp++;
        } else {
            t->gamma_index = -1;
            t->len_index = -1;
        }
    }
    for (i = 0; i < nl; i++) {
        const double *row = loads + 7 * i;
        int c;
        for (c = 0; c < 7; c++)
            if (!isfinite(row[c])) {
                msgf(msg, msglen, "loads[%d][%d] = %g must be finite", i, c, row[c]);
                status = TR_EINVAL;
                goto fail;
            }
        if (row[0] < 0.0 || row[0] > m->L * (1.0 + TR_BP_MERGE)) {
            msgf(msg, msglen, "loads[%d] s = %g m must lie in [0, L = %g]", i, row[0], m->L);
            status = TR_EINVAL;
            goto fail;
        }
        memcpy(m->load + 7 * i, row, 7 * sizeof(double));
        if (m->load[7 * i] > m->L) m->load[7 * i] = m->L;
    }
    memcpy(m->dist, dist, 3 * sizeof(double));
    m->has_dist = (dist[0] != 0.0 || dist[1] != 0.0 || dist[2] != 0.0);

    /* ---- breakpoints */
    if (opt->shooting_segments < 1 || opt->shooting_segments > TR_MAX_SHOOTING_SEGMENTS) {
        msgf(msg, msglen, "shooting_segments = %d must lie in [1, %d]", opt->shooting_segments,
             TR_MAX_SHOOTING_SEGMENTS);
        status = TR_EINVAL;
        goto fail;
    }
    m->nshoot = opt->shooting_segments;
    cand = (double *)malloc((size_t)(nt + nl + 2 + m->nshoot) * sizeof(double));
    if (!cand) {
        status = TR_ENOMEM;
        goto fail;
    }
    cand[nc++] = 0.0;
    cand[nc++] = m->L;
    for (i = 1; i < m->nshoot; i++) cand[nc++] = m->L * ((double)i / m->nshoot);
    for (i = 0; i < nt; i++) cand[nc++] = m->tendon[i].t;
    for (i = 0; i < nl; i++) {
        const double *row = m->load + 7 * i;
        int nz = 0, c;
        for (c = 1; c < 7; c++) nz |= (row[c] != 0.0);
        /* a zero load still makes a breakpoint (compliance probes need one) */
        (void)nz;
        cand[nc++] = row[0];
    }
    qsort(cand, nc, sizeof(double), cmp_double);
    m->bp = (double *)malloc((size_t)nc * sizeof(double));
    if (!m->bp) {
        status = TR_ENOMEM;
        goto fail;
    }
    {
        int nb = 0;
        for (i = 0; i < nc; i++) {
            if (nb > 0 && cand[i] - m->bp[nb - 1] <= TR_BP_MERGE * m->L) continue;
            m->bp[nb++] = cand[i];
        }
        /* snap the last to L exactly */
        if (m->L - m->bp[nb - 1] <= TR_BP_MERGE * m->L) m->bp[nb - 1] = m->L;
        m->nseg = nb - 1;
    }
    m->bpF = (double *)calloc((size_t)3 * (m->nseg + 1), sizeof(double));
    m->bpM = (double *)calloc((size_t)3 * (m->nseg + 1), sizeof(double));
    m->seg_act_start = (int *)calloc((size_t)m->nseg + 1, sizeof(int));
    m->seg_act = (int *)calloc((size_t)(nt > 0 ? nt * m->nseg : 1), sizeof(int));
    m->bp_node = (int *)calloc((size_t)m->nseg + 1, sizeof(int));
    if (!m->bpF || !m->bpM || !m->seg_act_start || !m->seg_act || !m->bp_node) {
        status = TR_ENOMEM;
        goto fail;
    }
    for (i = 1; i < m->nshoot; i++) m->bp_node[find_bp(m, m->L * ((double)i / m->nshoot))] = i;
    m->bp_jump = (int *)calloc((size_t)m->nseg + 1, sizeof(int));
    if (!m->bp_jump) {
        status = TR_ENOMEM;
        goto fail;
    }
    for (i = 0; i < nt; i++) m->bp_jump[find_bp(m, m->tendon[i].t)] = 1;
    for (i = 0; i < nl; i++) m->bp_jump[find_bp(m, m->load[7 * i])] = 1;
    for (i = 0; i < nt; i++) {
        m->tendon[i].end_bp = find_bp(m, m->tendon[i].t);
        m->tendon[i].t = m->bp[m->tendon[i].end_bp];
    }
    for (i = 0; i < nl; i++) {
        const double *row = m->load + 7 * i;
        const int b = find_bp(m, row[0]);
        int c;
        for (c = 0; c < 3; c++) {
            m->bpF[3 * b + c] += row[1 + c];
            m->bpM[3 * b + c] += row[4 + c];
        }
    }
    {
        int nact = 0;
        for (k = 0; k < m->nseg; k++) {
            m->seg_act_start[k] = nact;
            for (i = 0; i < nt; i++)
                if (m->tendon[i].end_bp > k) m->seg_act[nact++] = i;
        }
        m->seg_act_start[m->nseg] = nact;
    }

    /* ---- formulation */
    {
        int planar = !opt->force_spatial;
        for (i = 0; i < nt && planar; i++)
            if (fabs(m->tendon[i].sphi) > TR_PLANAR_SIN) planar = 0;
        for (i = 0; i < nl && planar; i++) {
            const double *row = m->load + 7 * i;
            if (row[2] != 0.0 || row[4] != 0.0 || row[6] != 0.0) planar = 0;
        }
        if (dist[1] != 0.0) planar = 0;
        m->planar = planar;
        if (planar)
            for (i = 0; i < nt; i++) {
                tr_tendon *t = &m->tendon[i];
                const double h = sqrt(1.0 + t->a * t->a);
                t->cphi = t->cphi > 0.0 ? 1.0 : -1.0;
                t->sphi = 0.0;
                t->t0[0] = t->a * t->cphi / h;
                t->t0[1] = 0.0;
                t->t0[2] = 1.0 / h;
                t->rt0[0] = 0.0;
                t->rt0[1] = -t->b * t->cphi / h;
                t->rt0[2] = 0.0;
            }
    }
    m->ndisp = ndisp;
    m->n_base = m->planar ? 6 : 18;
    m->n_states = m->n_base + ndisp;
    m->n_unknowns = (m->planar ? 3 : 6) + ndisp + (m->nshoot - 1) * m->n_states;
    m->n_states_rec = m->n_base + nt;
    m->n_stretch = 0;
    for (i = 0; i < nt; i++)
        if (m->tendon[i].control == TR_DISPLACEMENT && isfinite(m->tendon[i].EA)) m->n_stretch++;
    m->F_s = m->EI / (m->L * m->L);
    m->M_s = m->EI / m->L;
    m->tau_s = rmax > 0.0 ? m->EI / (rmax * m->L) : m->F_s;
    m->len_s = rmax > 0.0 ? rmax : m->L;
    for (i = 0; i < 18; i++) m->xstate_scale[i] = 1.0;
    if (m->planar) {
        m->xstate_scale[TR_YP_X] = m->xstate_scale[TR_YP_Z] = m->L;
        m->xstate_scale[TR_YP_N1] = m->xstate_scale[TR_YP_N3] = m->F_s;
        m->xstate_scale[TR_YP_M] = m->M_s;
    } else {
        for (i = 0; i < 3; i++) {
            m->xstate_scale[TR_Y_P + i] = m->L;
            m->xstate_scale[TR_Y_N + i] = m->F_s;
            m->xstate_scale[TR_Y_M + i] = m->M_s;
        }
    }

    status = set_rest_lengths(m, m->scene_message, sizeof m->scene_message);
    if (status == TR_OK) status = check_indeterminate(m, m->scene_message, sizeof m->scene_message);
    if (status == TR_EINVAL || status == TR_ENOMEM) {
        msgf(msg, msglen, "%s", m->scene_message);
        goto fail;
    }
    m->scene_status = status;
    status = TR_OK;

    free(cand);
    *out = m;
    return TR_OK;
fail:
    if (status == TR_ENOMEM) msgf(msg, msglen, "out of memory while compiling the model");
    free(cand);
    tr_model_free(m);
    return status;
}
