/*
 * tr_tendons.c -- what a tendon set needs beyond its geometry: the rest lengths
 * that give each tendon its pretension in the unloaded robot, and the check for
 * opposing inextensible tendons on an inextensible backbone (statically
 * indeterminate, or no equilibrium), which depends on the displacements.
 */
#include <math.h>
#include <stdio.h>

#include "tendonrod.h"
#include "tr_internal.h"

/* Pretension: rest lengths so that each tendon holds its pretension at q = 0 in
 * the straight robot, uniformly compressed by the pretensions if Cosserat. */
int tr_rest_lengths(tr_model *m, char *msg, size_t msglen)
{
    int i, k, any = 0;
    for (i = 0; i < m->nt; i++) {
        tr_tendon *t = &m->tendon[i];
        t->sref = tr_reference_length(m, i);
        t->rest = t->sref;
        t->rest_dev = 0.0;
        if (t->pretension != 0.0) any = 1;
    }
    if (!any) return TR_OK;
    if (m->n_routed > 0) {
        tr_msgf(msg, msglen,
                "pretension with helical or piecewise tendon paths is not supported (the balance "
                "of the unloaded robot is not checked for them); prescribe the tensions or "
                "displacements instead");
        return TR_EPRETENSION;
    }
    /* A precurvature bending about body x, y keeps every radial channel's tangent at
     * e3 + u* x r along e3: a balanced set then holds the unstressed arc, compressed
     * uniformly (n_b = -sum tau_p e3, m_b = 0), and the steps below are exact for parallel
     * tendons.  A pretwist turns the channels: the pretensioned robot twists. */
    for (k = 0; k < m->nsec; k++)
        if (m->sec[TR_SC_NCOL * k + TR_SC_U + 2] != 0.0) {
            tr_msgf(msg, msglen,
                    "pretension on a pretwisted backbone (sections[%d] uz = %g 1/m) is not "
                    "supported: the pull along its turning channels twists the unloaded robot, "
                    "so the pretensions are not held in the unstressed shape; prescribe the "
                    "tensions or displacements instead",
                    k, m->sec[TR_SC_NCOL * k + TR_SC_U + 2]);
            return TR_EPRETENSION;
        }
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
                tr_msgf(msg, msglen,
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
            tr_msgf(msg, msglen,
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
            tr_msgf(msg, msglen, "tendon %d: pretension = %g N must be >= 0 (a tendon cannot push)",
                    i, t->pretension);
            return TR_EINVAL;
        }
        /* len - sref accumulated without cancellation: per segment
         * sqrt(a^2 + v3^2) - c = (v3^2 - 1) / (sqrt(a^2 + v3^2) + c), v3^2 - 1 = e (2 + e) */
        for (k = 0; k < t->end_bp; k++) {
            double e = 0.0; /* v3 - 1 */
            const double c = t->wref;
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
                    en = n3 / m->seg_rod[TR_SR_NCOL * k + TR_SR_EA];
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
int tr_check_indeterminate(const tr_model *m, char *msg, size_t msglen)
{
    int i, j, l, n = 0;
    int idx[64];
    if (!m->kirchhoff) return TR_OK;
    /* the bound sum c_i s_i >= sum c_i s_ref,i holds for a reference shape whose channels
     * run at u* x r along e3, i.e. no pretwist */
    for (i = 0; i < m->nsec; i++)
        if (m->sec[TR_SC_NCOL * i + TR_SC_U + 2] != 0.0) return TR_OK;
    for (i = 0; i < m->nt && n < 64; i++) {
        const tr_tendon *t = &m->tendon[i];
        /* the pairs compare linear routes (b and a along phi) */
        if (t->control == TR_DISPLACEMENT && !isfinite(t->EA) && t->route == TR_ROUTE_LINEAR)
            idx[n++] = i;
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
                    tr_msgf(
                        msg, msglen,
                        "no equilibrium: %s are opposing inextensible tendons on an inextensible "
                        "backbone and their displacements retract them together (weighted sum "
                        "%.6g m > 0), which would need the backbone to shorten; release one of "
                        "them, or give the tendons a finite EA or the backbone an extension "
                        "stiffness",
                        names, Q / csum);
                    return TR_ENOEQUILIBRIUM;
                }
                if (Q >= -ncomb) {
                    tr_msgf(msg, msglen,
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
