/*
 * tr_section.c -- the rod's state at a section, outside the right-hand side: a tendon's
 * unit tangent and offset, the pose and internal loads in the world frame, and the pulls
 * of the tendons across a section with their derivative (the jumps at breakpoints).
 */
#include <math.h>
#include <string.h>

#include "tendonrod.h"
#include "tr_internal.h"
#include "tru_math.h"

/* Tendon i's unnormalised tangent w = v + u x r + r' (body frame) on segment seg at s, for
 * the strains u, v; its offset r. */
static void tendon_w(const tr_model *m, int i, int seg, double s, const double u[3],
                     const double v[3], double r[3], double w[3])
{
    double rp[3];
    tr_tendon_offset(m, i, seg, s, r, rp);
    tru_cross3(w, u, r);
    w[0] += v[0] + rp[0];
    w[1] += v[1] + rp[1];
    w[2] += v[2];
}

void tr_tendon_tangent(const tr_model *m, int i, double s, const double *y, double that[3],
                       double r[3])
{
    const tr_tendon *td = &m->tendon[i];
    /* the segment just proximal of its anchor */
    const int seg = td->end_bp > 0 ? td->end_bp - 1 : 0;
    const double *sr = m->seg_rod + TR_SR_NCOL * seg;
    double w[3], nw;
    if (m->planar) {
        const double kap = y[TR_YP_M] / sr[TR_SR_EI] + sr[TR_SR_U + 1];
        const double rho = td->cphi * (td->a * s + td->b);
        double v1 = 0.0, v3 = 1.0;
        if (!m->kirchhoff) {
            v1 = y[TR_YP_N1] / sr[TR_SR_GA];
            v3 = 1.0 + y[TR_YP_N3] / sr[TR_SR_EA];
        }
        w[0] = v1 + td->cphi * td->a;
        w[1] = 0.0;
        w[2] = v3 - kap * rho;
        r[0] = rho;
        r[1] = 0.0;
        r[2] = 0.0;
    } else {
        const double *nb = y + TR_Y_N, *mb = y + TR_Y_M;
        const double u[3] = {mb[0] / sr[TR_SR_EI] + sr[TR_SR_U],
                             mb[1] / sr[TR_SR_EI] + sr[TR_SR_U + 1],
                             mb[2] / sr[TR_SR_GJ] + sr[TR_SR_U + 2]};
        double v[3] = {0.0, 0.0, 1.0};
        if (!m->kirchhoff) {
            v[0] = nb[0] / sr[TR_SR_GA];
            v[1] = nb[1] / sr[TR_SR_GA];
            v[2] = 1.0 + nb[2] / sr[TR_SR_EA];
        }
        tendon_w(m, i, seg, s, u, v, r, w);
    }
    nw = tru_norm3(w);
    that[0] = w[0] / nw;
    that[1] = w[1] / nw;
    that[2] = w[2] / nw;
}

void tr_state_world(const tr_model *m, const double *y, double p[3], double R[9], double n[3],
                    double mom[3])
{
    if (m->planar) {
        const double th = y[TR_YP_TH], c = cos(th), s = sin(th);
        const double n1 = y[TR_YP_N1], n3 = y[TR_YP_N3];
        p[0] = y[TR_YP_X];
        p[1] = 0.0;
        p[2] = y[TR_YP_Z];
        R[0] = c;
        R[1] = 0.0;
        R[2] = s;
        R[3] = 0.0;
        R[4] = 1.0;
        R[5] = 0.0;
        R[6] = -s;
        R[7] = 0.0;
        R[8] = c;
        n[0] = c * n1 + s * n3;
        n[1] = 0.0;
        n[2] = -s * n1 + c * n3;
        mom[0] = 0.0;
        mom[1] = y[TR_YP_M];
        mom[2] = 0.0;
    } else {
        memcpy(p, y + TR_Y_P, 3 * sizeof(double));
        memcpy(R, y + TR_Y_R, 9 * sizeof(double));
        tru_matvec3(n, R, y + TR_Y_N);
        tru_matvec3(mom, R, y + TR_Y_M);
    }
}

/* Pulls of the tendons active on segment seg at s (tensions tau_all (nt) [N]), body frame,
 * for backbone force
 * nb and moment mb (3-vectors; planar scenes embed as (n1, 0, n3), (0, m2, 0)):
 * fn = sum tau t^, fm = sum tau r x t^.  If J6 != NULL it receives the 6x6
 * derivative of (fn, fm) with respect to (nb, mb), row-major. */
void tr_section_pulls(const tr_model *m, const double *tau_all, int seg, double s,
                      const double nb[3], const double mb[3], double fn[3], double fm[3],
                      double *J6)
{
    const double *sr = m->seg_rod + TR_SR_NCOL * seg, *us = sr + TR_SR_U;
    const double kb[3] = {1.0 / sr[TR_SR_EI], 1.0 / sr[TR_SR_EI], 1.0 / sr[TR_SR_GJ]};
    const double ks[3] = {m->kirchhoff ? 0.0 : 1.0 / sr[TR_SR_GA],
                          m->kirchhoff ? 0.0 : 1.0 / sr[TR_SR_GA],
                          m->kirchhoff ? 0.0 : 1.0 / sr[TR_SR_EA]};
    const double u[3] = {mb[0] * kb[0] + us[0], mb[1] * kb[1] + us[1], mb[2] * kb[2] + us[2]};
    const double v[3] = {nb[0] * ks[0], nb[1] * ks[1], 1.0 + nb[2] * ks[2]};
    int c, q, r_, c_;
    fn[0] = fn[1] = fn[2] = fm[0] = fm[1] = fm[2] = 0.0;
    if (J6) memset(J6, 0, 36 * sizeof(double));
    for (c = m->seg_act_start[seg]; c < m->seg_act_start[seg + 1]; c++) {
        const int i = m->seg_act[c];
        const double tau = tau_all[i];
        double r[3], w[3], nw, th[3], rt[3];
        if (!(tau > 0.0)) continue;
        tendon_w(m, i, seg, s, u, v, r, w);
        nw = tru_norm3(w);
        for (q = 0; q < 3; q++) th[q] = w[q] / nw;
        tru_cross3(rt, r, th);
        for (q = 0; q < 3; q++) {
            fn[q] += tau * th[q];
            fm[q] += tau * rt[q];
        }
        if (J6) {
            /* A = tau (I - t t^T)/|w|;  d(tau t)/dnb = A Kse^-1, d(tau t)/dmb = -A r^ Kbt^-1;
             * the moment rows are r^ times the force rows */
            double A[9], S[9], AS[9], SA[9], SAS[9];
            for (r_ = 0; r_ < 3; r_++)
                for (c_ = 0; c_ < 3; c_++)
                    A[3 * r_ + c_] = tau * ((r_ == c_) - th[r_] * th[c_]) / nw;
            tru_skew3(S, r);
            tru_matmul3(AS, A, S);
            tru_matmul3(SA, S, A);
            tru_matmul3(SAS, S, AS);
            for (r_ = 0; r_ < 3; r_++)
                for (c_ = 0; c_ < 3; c_++) {
                    J6[6 * r_ + c_] += A[3 * r_ + c_] * ks[c_];
                    J6[6 * r_ + c_ + 3] += -AS[3 * r_ + c_] * kb[c_];
                    J6[6 * (r_ + 3) + c_] += SA[3 * r_ + c_] * ks[c_];
                    J6[6 * (r_ + 3) + c_ + 3] += -SAS[3 * r_ + c_] * kb[c_];
                }
        }
    }
}
