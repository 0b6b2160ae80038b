/*
 * tr_backbone.c -- the backbone's sections: rigidities and precurvature per integration
 * segment, and what the precurved unstressed robot gives the tendons (their tangent at
 * the base and their reference path length).
 *
 * A section has constant rigidities and a constant precurvature u* (body frame): its
 * unstressed shape is a circular arc (u* in the x-y plane) or a helix, and its
 * constitutive law is m_b = K_bt (u - u*), n_b = K_se (v - e3).  Section ends are
 * breakpoints, so every integration segment lies in one section.  A scene without
 * sections is one uniform straight section made of the rod row.
 */
#include <math.h>
#include <string.h>

#include "tendonrod.h"
#include "tr_internal.h"

/* Gauss-Legendre nodes (on [-1, 1], positive half) and weights, 8 points. */
static const double gl_x[4] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267,
                               0.9602898564975363};
static const double gl_w[4] = {0.3626837833783620, 0.3137066678522765, 0.2223810344533745,
                               0.1012285362903763};

int tr_sections_planar(const double *sections, int nsec)
{
    int j;
    for (j = 0; j < nsec; j++) {
        const double *row = sections + TR_SC_NCOL * j;
        if (row[TR_SC_U] != 0.0 || row[TR_SC_U + 2] != 0.0) return 0;
    }
    return 1;
}

int tr_read_sections(tr_model *m, const double *sections, int nsec, char *msg, size_t msglen)
{
    static const char *col[TR_SC_NCOL] = {"end", "EI", "GJ", "EA", "GA", "ux", "uy", "uz"};
    double prev = 0.0;
    int j, c;
    m->nsec = nsec;
    m->precurved = 0;
    for (j = 0; j < nsec; j++) {
        const double *row = sections + TR_SC_NCOL * j;
        for (c = 0; c < TR_SC_NCOL; c++) {
            const int may_inf = (c == TR_SC_EA || c == TR_SC_GA) && m->kirchhoff;
            if (isnan(row[c]) || (!may_inf && !isfinite(row[c]))) {
                tr_msgf(msg, msglen, "sections[%d] %s = %g must be finite", j, col[c], row[c]);
                return TR_EINVAL;
            }
        }
        for (c = TR_SC_EI; c <= TR_SC_GA; c++) {
            const int axial = c >= TR_SC_EA;
            const double lo = axial ? TR_EA_MIN : TR_ROD_MIN, hi = axial ? TR_EA_MAX : TR_ROD_MAX;
            if (!(row[c] > 0.0) || (isfinite(row[c]) && (row[c] < lo || row[c] > hi))) {
                tr_msgf(msg, msglen, "sections[%d] %s = %g must lie in [%g, %g]", j, col[c], row[c],
                        lo, hi);
                return TR_EINVAL;
            }
        }
        if (!(row[TR_SC_END] > prev) ||
            (j == nsec - 1 && fabs(row[TR_SC_END] - m->L) > 1e-12 * m->L) ||
            row[TR_SC_END] > m->L * (1.0 + 1e-12)) {
            tr_msgf(msg, msglen,
                    "sections[%d] end = %g m must exceed the previous end %g m, and the last "
                    "end must be L = %g m",
                    j, row[TR_SC_END], prev, m->L);
            return TR_EINVAL;
        }
        for (c = 0; c < 3; c++)
            if (fabs(row[TR_SC_U + c]) * m->L > TR_ROD_MAX) {
                tr_msgf(msg, msglen, "sections[%d] %s = %g 1/m is out of range", j,
                        col[TR_SC_U + c], row[TR_SC_U + c]);
                return TR_EINVAL;
            }
        if (row[TR_SC_U] != 0.0 || row[TR_SC_U + 1] != 0.0 || row[TR_SC_U + 2] != 0.0)
            m->precurved = 1;
        memcpy(m->sec + TR_SC_NCOL * j, row, TR_SC_NCOL * sizeof(double));
        prev = row[TR_SC_END];
    }
    if (nsec > 0) m->sec[TR_SC_NCOL * (nsec - 1) + TR_SC_END] = m->L;
    return TR_OK;
}

void tr_fill_segment_rods(tr_model *m)
{
    int k, j = 0;
    m->rod_k[TR_SR_EI] = m->EI;
    m->rod_k[TR_SR_GJ] = m->GJ;
    m->rod_k[TR_SR_EA] = m->EA;
    m->rod_k[TR_SR_GA] = m->GA;
    m->rod_k[TR_SR_U] = m->rod_k[TR_SR_U + 1] = m->rod_k[TR_SR_U + 2] = 0.0;
    m->general = m->nsec > 0 || m->n_routed > 0;
    for (k = 0; k < m->nseg; k++) {
        double *sr = m->seg_rod + TR_SR_NCOL * k;
        if (m->nsec == 0) {
            sr[TR_SR_EI] = m->EI;
            sr[TR_SR_GJ] = m->GJ;
            sr[TR_SR_EA] = m->EA;
            sr[TR_SR_GA] = m->GA;
            sr[TR_SR_U] = sr[TR_SR_U + 1] = sr[TR_SR_U + 2] = 0.0;
            continue;
        }
        {
            /* the section holding the segment's midpoint */
            const double mid = 0.5 * (m->bp[k] + m->bp[k + 1]);
            const double *row;
            while (j < m->nsec - 1 && m->sec[TR_SC_NCOL * j + TR_SC_END] < mid) j++;
            row = m->sec + TR_SC_NCOL * j;
            sr[TR_SR_EI] = row[TR_SC_EI];
            sr[TR_SR_GJ] = row[TR_SC_GJ];
            sr[TR_SR_EA] = row[TR_SC_EA];
            sr[TR_SR_GA] = row[TR_SC_GA];
            memcpy(sr + TR_SR_U, row + TR_SC_U, 3 * sizeof(double));
        }
    }
}

void tr_tendon_wref(const tr_model *m, int i, int k, double s, double w[3])
{
    const double *us = m->seg_rod + TR_SR_NCOL * k + TR_SR_U;
    double r[3], rp[3];
    tr_tendon_offset(m, i, k, s, r, rp);
    w[0] = rp[0] + us[1] * r[2] - us[2] * r[1];
    w[1] = rp[1] + us[2] * r[0] - us[0] * r[2];
    w[2] = 1.0 + us[0] * r[1] - us[1] * r[0];
}

void tr_tendon_base_frame_straight(tr_tendon *t)
{
    const double h = t->wref;
    t->t0[0] = t->a * t->cphi / h;
    t->t0[1] = t->a * t->sphi / h;
    t->t0[2] = 1.0 / h;
    t->rt0[0] = t->b * t->sphi / h;
    t->rt0[1] = -t->b * t->cphi / h;
    t->rt0[2] = 0.0;
}

void tr_tendon_base_frame(const tr_model *m, int i)
{
    tr_tendon *t = &m->tendon[i];
    if (!m->precurved && t->route == TR_ROUTE_LINEAR) {
        tr_tendon_base_frame_straight(t);
    } else {
        double w[3], r[3], rp[3], h;
        int c;
        tr_tendon_wref(m, i, 0, 0.0, w);
        tr_tendon_offset(m, i, 0, 0.0, r, rp);
        h = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
        for (c = 0; c < 3; c++) t->t0[c] = w[c] / h;
        t->rt0[0] = r[1] * t->t0[2] - r[2] * t->t0[1];
        t->rt0[1] = r[2] * t->t0[0] - r[0] * t->t0[2];
        t->rt0[2] = r[0] * t->t0[1] - r[1] * t->t0[0];
    }
}

double tr_reference_length(const tr_model *m, int i)
{
    const tr_tendon *t = &m->tendon[i];
    double sum = 0.0;
    int k, p, g;
    if (!m->precurved && t->route == TR_ROUTE_LINEAR) return t->t * t->wref;
    for (k = 0; k < t->end_bp; k++) {
        const double h = (m->bp[k + 1] - m->bp[k]) / TR_REF_PANELS;
        for (p = 0; p < TR_REF_PANELS; p++) {
            const double mid = m->bp[k] + (p + 0.5) * h;
            for (g = 0; g < 8; g++) {
                const double x = g < 4 ? -gl_x[g] : gl_x[g - 4], wg = gl_w[g % 4];
                double w[3];
                tr_tendon_wref(m, i, k, mid + 0.5 * h * x, w);
                sum += 0.5 * h * wg * sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
            }
        }
    }
    return sum;
}

int tr_check_routing(const tr_model *m, char *msg, size_t msglen)
{
    int i, k, e;
    if (!m->precurved && m->n_routed == 0) return TR_OK;
    for (i = 0; i < m->nt; i++) {
        const tr_tendon *t = &m->tendon[i];
        for (k = 0; k < t->end_bp; k++)
            for (e = 0; e < 2; e++) {
                double w[3];
                tr_tendon_wref(m, i, k, m->bp[k + e], w);
                if (!(w[2] > 0.0)) {
                    tr_msgf(msg, msglen,
                            "tendons[%d]: its channel at s = %g m does not advance along the "
                            "unstressed backbone (1 + (u* x r)_z = %g <= 0: an offset beyond "
                            "the precurvature's centre): the channel would fold back",
                            i, m->bp[k + e], w[2]);
                    return TR_EINVAL;
                }
            }
    }
    return TR_OK;
}
