/*
 * tr_dyn_rhs.c -- the terms a time step of the dynamics adds to the spatial right-hand
 * side (tr_rod.c calls them where d->dyn is set; docs/guide/dynamics.md).
 */
#include <math.h>
#include <string.h>

#include "tendonrod.h"
#include "tr_internal.h"
#include "tru_math.h"

/* A time step's terms (tr_dyn_ctx, tr_internal.h), out of line: the static kernel pays
 * one predictable branch per hook.  The states n_b, m_b stay the whole internal force
 * and moment, viscous part included: with n = K_se (v - v* + eta v_t) and v_t = c0 v + v_h,
 *   v = (K_se^-1 n + v* - eta v_h) / (1 + eta c0)    (u alike with K_bt, u*),
 *   v' = (K_se^-1 n' - eta v_h') / (1 + eta c0)      (uniform within a segment),
 * so the tendons' A v' + G u' keep their form with K^-1 scaled by 1 / (1 + eta c0) and
 * the history's part moved to the right-hand side.  The velocities follow the pose:
 * q = R^T p_t, w^ = skew(R^T R_t) with p_t = c0 p + p_h, R_t = c0 R + R_h. */
int tr_dyn_strains(const tr_model *m, const tr_data *d, double s, const double *y, const double *sg,
                   const double *us, int pc, double du[3], double u[3], double v[3], double *ev3)
{
    tr_dyn_ctx *c = d->dyn;
    const double f = 1.0 / (1.0 + c->eta * c->c0);
    const double kb[3] = {sg[TR_SR_EI], sg[TR_SR_EI], sg[TR_SR_GJ]};
    const double *h;
    double *o;
    int j;
    if (d->seg == 0 && s == m->bp[0]) c->k = 0; /* a residual evaluation starts */
    if (c->k >= c->npt || d->rec || m->kirchhoff) return -1;
    h = c->hist + TR_DH_N * c->k;
    o = c->cur + TR_DH_N * c->k;
    v[0] = (y[TR_Y_N + 0] / sg[TR_SR_GA] - c->eta * h[TR_DH_V + 0]) * f;
    v[1] = (y[TR_Y_N + 1] / sg[TR_SR_GA] - c->eta * h[TR_DH_V + 1]) * f;
    v[2] = (y[TR_Y_N + 2] / sg[TR_SR_EA] + 1.0 - c->eta * h[TR_DH_V + 2]) * f;
    *ev3 = v[2] - 1.0;
    for (j = 0; j < 3; j++) {
        const double ust = pc ? us[j] : 0.0;
        u[j] = (y[TR_Y_M + j] / kb[j] + ust - c->eta * h[TR_DH_U + j]) * f;
        du[j] = u[j] - ust;
    }
    memcpy(o + TR_DH_P, y + TR_Y_P, 12 * sizeof(double)); /* p, R */
    memcpy(o + TR_DH_V, v, 3 * sizeof(double));
    memcpy(o + TR_DH_U, u, 3 * sizeof(double));
    o[TR_DH_EE] =
        0.5 * (sg[TR_SR_GA] * (v[0] * v[0] + v[1] * v[1]) + sg[TR_SR_EA] * (*ev3) * (*ev3) +
               kb[0] * du[0] * du[0] + kb[1] * du[1] * du[1] + kb[2] * du[2] * du[2]);
    return 0;
}

/* The inertia, drag and damping-history terms of the right-hand side rhs (6), given the
 * tendons' accumulators (A = sc I - TT, G = -(r^ + TQ), B = r^ - TQ^T,
 * H = sr2 I - RR - QQ); the velocities and energy densities into the stage point. */
void tr_dyn_loads(const tr_data *d, const double *y, const double sg[], int coupled, double rhs[6],
                  double sc, const double sr[3], double sr2, const double RR0[9],
                  const double TQ[9], const double QQ[9], const double TT[9])
{
    tr_dyn_ctx *c = d->dyn;
    const double c0 = c->c0, f = 1.0 / (1.0 + c->eta * c0);
    const double *h = c->hist + TR_DH_N * c->k, *R = y + TR_Y_R;
    double *o = c->cur + TR_DH_N * c->k;
    double pt[3], q[3], Rt[9], W[9], w[3], qt[3], wt[3], a[3], b[3], jw[3];
    const double kb[3] = {sg[TR_SR_EI], sg[TR_SR_EI], sg[TR_SR_GJ]};
    const double ks[3] = {sg[TR_SR_GA], sg[TR_SR_GA], sg[TR_SR_EA]};
    double pd = 0.0;
    int j;
    for (j = 0; j < 3; j++) pt[j] = c0 * y[TR_Y_P + j] + h[TR_DH_P + j];
    tru_mattvec3(q, R, pt);
    for (j = 0; j < 9; j++) Rt[j] = c0 * R[j] + h[TR_DH_R + j];
    for (j = 0; j < 9; j++) /* W = R^T R_t */
        W[j] = R[j / 3] * Rt[j % 3] + R[3 + j / 3] * Rt[3 + j % 3] + R[6 + j / 3] * Rt[6 + j % 3];
    w[0] = 0.5 * (W[7] - W[5]);
    w[1] = 0.5 * (W[2] - W[6]);
    w[2] = 0.5 * (W[3] - W[1]);
    for (j = 0; j < 3; j++) {
        qt[j] = c0 * q[j] + h[TR_DH_Q + j];
        wt[j] = c0 * w[j] + h[TR_DH_W + j];
        jw[j] = c->rhoJ[j] * w[j];
    }
    tru_cross3(a, w, q);
    tru_cross3(b, w, jw);
    for (j = 0; j < 3; j++) {
        rhs[j] += c->rhoA * (qt[j] + a[j]) + c->drag * q[j] * fabs(q[j]);
        rhs[3 + j] += c->rhoJ[j] * wt[j] + b[j];
        pd += c->drag * fabs(q[j]) * q[j] * q[j];
    }
    if (coupled && c->eta > 0.0) {
        /* the history's part of v', u': e_v = eta f v_h', e_u = eta f u_h' */
        double ev[3], eu[3], RR[9];
        memcpy(RR, RR0, sizeof RR);
        RR[3] = RR[1];
        for (j = 0; j < 3; j++) {
            ev[j] = c->eta * f * h[TR_DH_VS + j];
            eu[j] = c->eta * f * h[TR_DH_US + j];
        }
        for (j = 0; j < 3; j++) {
            int l;
            double r1 = sc * ev[j], r2 = sr2 * eu[j];
            for (l = 0; l < 3; l++) {
                r1 += -TT[3 * j + l] * ev[l] - TQ[3 * j + l] * eu[l];
                r2 += -TQ[3 * l + j] * ev[l] - (RR[3 * j + l] + QQ[3 * j + l]) * eu[l];
            }
            rhs[j] += r1;
            rhs[3 + j] += r2;
        }
        /* the r^ parts: -r^ e_u in the force row, r^ e_v in the moment row */
        tru_cross3(a, sr, eu);
        tru_cross3(b, sr, ev);
        for (j = 0; j < 3; j++) {
            rhs[j] -= a[j];
            rhs[3 + j] += b[j];
        }
    }
    memcpy(o + TR_DH_Q, q, 3 * sizeof(double));
    memcpy(o + TR_DH_W, w, 3 * sizeof(double));
    o[TR_DH_EK] = 0.5 * (c->rhoA * (q[0] * q[0] + q[1] * q[1] + q[2] * q[2]) + jw[0] * w[0] +
                         jw[1] * w[1] + jw[2] * w[2]);
    if (c->eta > 0.0)
        for (j = 0; j < 3; j++) {
            const double vt = c0 * o[TR_DH_V + j] + h[TR_DH_V + j];
            const double ut = c0 * o[TR_DH_U + j] + h[TR_DH_U + j];
            pd += c->eta * (ks[j] * vt * vt + kb[j] * ut * ut);
        }
    o[TR_DH_PD] = pd;
}

/* The stage point's v', u' from the solved (n_b', m_b') in dy; the next point. */
void tr_dyn_store(const tr_data *d, const double *dy, const double sg[])
{
    tr_dyn_ctx *c = d->dyn;
    const double f = 1.0 / (1.0 + c->eta * c->c0);
    const double *h = c->hist + TR_DH_N * c->k;
    double *o = c->cur + TR_DH_N * c->k;
    const double kb[3] = {sg[TR_SR_EI], sg[TR_SR_EI], sg[TR_SR_GJ]};
    const double ks[3] = {sg[TR_SR_GA], sg[TR_SR_GA], sg[TR_SR_EA]};
    int j;
    for (j = 0; j < 3; j++) {
        o[TR_DH_VS + j] = (dy[TR_Y_N + j] / ks[j] - c->eta * h[TR_DH_VS + j]) * f;
        o[TR_DH_US + j] = (dy[TR_Y_M + j] / kb[j] - c->eta * h[TR_DH_US + j]) * f;
    }
    c->k++;
}
