/*
 * tr_rod.c -- right-hand sides of the rod/tendon ODE (docs/model.md).
 *
 * Body-frame equilibrium with the tendon loads a + A v' + G u' (force) and
 * b + B v' + H u' (moment); internal force and moment n_b, m_b are the states
 * (never v itself), so with the substitution v' = K_se^-1 n_b', u' = K_bt^-1 m_b'
 * the linear system per evaluation is
 *
 *   [ I + A K_se^-1   G K_bt^-1     ] [n_b']   [ -u x n_b - a - f_e       ]
 *   [ B K_se^-1       I + H K_bt^-1 ] [m_b'] = [ -u x m_b - v x n_b - b   ]
 *
 * (Kirchhoff: v = e3, v' = 0: only the 3x3 moment block, then n_b' from the
 * first row).  Every matrix is O(1), whatever the stiffness ratios.
 * Four variants: spatial/planar x Kirchhoff/Cosserat.  Slack tendons (tau = 0)
 * contribute only their path length.  With channel friction (tr_friction.c) the tendons'
 * tensions vary along s, and their tangential loads enter the same system by fixed-point
 * iteration (docs/model.md, Section 3).
 */
#include <math.h>
#include <string.h>
#include <gsl/gsl_errno.h>

#include "tendonrod.h"
#include "tr_internal.h"
#include "tru_math.h"

/* Both kernels take `gen` = m->general: 0 for a uniform straight rod with linear tendons
 * (the rod's own rigidities, no precurvature, no routes), 1 for sections or routes.  (A
 * specialisation per value, forced by always_inline into noinline wrappers, measured 15 %
 * slower per spatial evaluation than these predictable branches: bench/compare_core.py.) */

/* ------------------------------------------------------------- spatial */
/* x = M^-1 b for the 3 x 3 row-major M by Cramer's rule; -1 if M is singular. */
static int solve3(const double M[9], const double b[3], double x[3])
{
    const double c00 = M[4] * M[8] - M[5] * M[7];
    const double c01 = M[5] * M[6] - M[3] * M[8];
    const double c02 = M[3] * M[7] - M[4] * M[6];
    const double det = M[0] * c00 + M[1] * c01 + M[2] * c02;
    if (!(fabs(det) > 0.0)) return -1;
    x[0] = (c00 * b[0] + (M[2] * M[7] - M[1] * M[8]) * b[1] + (M[1] * M[5] - M[2] * M[4]) * b[2]) /
           det;
    x[1] = (c01 * b[0] + (M[0] * M[8] - M[2] * M[6]) * b[1] + (M[2] * M[3] - M[0] * M[5]) * b[2]) /
           det;
    x[2] = (c02 * b[0] + (M[1] * M[6] - M[0] * M[7]) * b[1] + (M[0] * M[4] - M[1] * M[3]) * b[2]) /
           det;
    return 0;
}

/* The inverse of the 3 x 3 row-major M by cofactors; -1 if M is singular. */
static int inv3(const double M[9], double Mi[9])
{
    const double c00 = M[4] * M[8] - M[5] * M[7];
    const double c01 = M[5] * M[6] - M[3] * M[8];
    const double c02 = M[3] * M[7] - M[4] * M[6];
    const double det = M[0] * c00 + M[1] * c01 + M[2] * c02;
    double idet;
    if (!(fabs(det) > 0.0)) return -1;
    idet = 1.0 / det;
    Mi[0] = c00 * idet;
    Mi[1] = (M[2] * M[7] - M[1] * M[8]) * idet;
    Mi[2] = (M[1] * M[5] - M[2] * M[4]) * idet;
    Mi[3] = c01 * idet;
    Mi[4] = (M[0] * M[8] - M[2] * M[6]) * idet;
    Mi[5] = (M[2] * M[3] - M[0] * M[5]) * idet;
    Mi[6] = c02 * idet;
    Mi[7] = (M[1] * M[6] - M[0] * M[7]) * idet;
    Mi[8] = (M[0] * M[4] - M[1] * M[3]) * idet;
    return 0;
}

/* Friction's code sits out of line and the solves below inline into the hot kernel, as the
 * code they replace was (bench/compare_core.py; callgrind: the frictionless kernel's
 * instructions as before). */
#if defined(__GNUC__)
#define TR_HOT_INLINE  static inline __attribute__((always_inline))
#define TR_COLD        static __attribute__((noinline, cold))
#define TR_UNLIKELY(x) __builtin_expect(!!(x), 0)
#else
#define TR_HOT_INLINE  static inline
#define TR_COLD        static
#define TR_UNLIKELY(x) (x)
#endif

/* A frictional tendon's rates beyond its deficit (dl: the state derivatives after the base
 * states, slot its path-length slot or -1): the stretch its varying tension adds to its
 * length integral, |w| (tau(0) - tau) / (EA + tau) (docs/model.md, Section 5), and in the
 * recording pass its rest length's rate |w| / (1 + tau/EA).  Kept out of line: the
 * frictionless kernel pays one predictable branch. */
TR_COLD void fric_rates(const tr_data *d, int i, const tr_tendon *td, double tau, double nw,
                        double *dl, int slot, int nlen, int nf)
{
    const double ea = td->EA * d->ea_scale;
    if (slot >= 0 && isfinite(td->EA)) dl[slot] += nw * (d->tau[i] - tau) / (ea + tau);
    if (d->rec) dl[nlen + nf + td->fric_index] = isfinite(td->EA) ? nw / (1.0 + tau / ea) : nw;
}

/* The tendons' local tensions at y (tr_tensions_at), out of line: the frictionless kernel
 * reads d->tau itself. */
TR_COLD const double *fric_tensions(const tr_model *m, const tr_data *d, const double *y)
{
    return tr_tensions_at(m, d, y);
}

/* A frictional taut tendon's row of the friction iteration (TR_FRIC_NCOL numbers, see
 * tr_internal.h): its slot, slide mu, tau/|w|, t (3), r (3), a_i (3). */
TR_COLD void fric_record(double *f, const tr_data *d, const tr_tendon *td, double ct,
                         const double t[3], const double r[3], const double ai[3])
{
    f[0] = td->fric_index;
    f[1] = td->slide * td->mu * d->lam_fric;
    f[2] = ct;
    memcpy(f + 3, t, 3 * sizeof(double));
    memcpy(f + 6, r, 3 * sizeof(double));
    memcpy(f + 9, ai, 3 * sizeof(double));
}

/* Zero the friction states' rates (dfric: nf deficits, then nf rest lengths in the
 * recording pass) and the normal loads of the kink test. */
TR_COLD void fric_reset(const tr_data *d, int nf, double *dfric)
{
    int j;
    for (j = 0; j < (d->rec ? 2 : 1) * nf; j++) dfric[j] = 0.0;
    for (j = 0; j < 3 * nf; j++) d->fric_g[j] = 0.0;
}

/* The body-frame system [I + A K_se^-1, G K_bt^-1; B K_se^-1, I + H K_bt^-1] of one
 * evaluation, set up once and solved for one or more right-hand sides (friction). */
typedef struct {
    int kirch;
    double kb[3], ks[3];             /* K_bt^-1, K_se^-1 (0 on a Kirchhoff rod) */
    double S[9], Gm[9];              /* the moment block I + H K_bt^-1 and G */
    double Q[9], SR[9], Si[9], Z[9]; /* Cosserat: G K_bt^-1, S^-1 B K_se^-1, S^-1, complement */
} sys6;

TR_HOT_INLINE int sys6_setup(sys6 *q, const double sr[3], double sr2, double sc, const double RR[9],
                             const double TQ[9], const double QQ[9], const double TT[9])
{
    double Hm[9], Sr[9], Rb[9];
    int r_, c_;
    tru_skew3(Sr, sr);
    for (r_ = 0; r_ < 9; r_++) {
        q->Gm[r_] = -(Sr[r_] + TQ[r_]);
        Hm[r_] = -RR[r_] - QQ[r_];
    }
    Hm[0] += sr2;
    Hm[4] += sr2;
    Hm[8] += sr2;
    for (r_ = 0; r_ < 3; r_++)
        for (c_ = 0; c_ < 3; c_++)
            q->S[3 * r_ + c_] = (r_ == c_ ? 1.0 : 0.0) + Hm[3 * r_ + c_] * q->kb[c_];
    if (q->kirch) return 0;
    /* the 6 x 6 system [P Q; R S] [n'; m'] = [rhs1; rhs2] with P = I + A K_se^-1,
     * Q = G K_bt^-1, R = B K_se^-1, by its Schur complement on S:
     * (P - Q S^-1 R) n' = rhs1 - Q S^-1 rhs2, m' = S^-1 rhs2 - S^-1 R n'.
     * P is I up to tau/EA, so the complement is as well conditioned as S. */
    if (inv3(q->S, q->Si) != 0) return -1;
    for (r_ = 0; r_ < 3; r_++)
        for (c_ = 0; c_ < 3; c_++) {
            /* A = sc I - TT;  B = r^ sum - Q T^T = Sr - TQ^T */
            const double id = (r_ == c_ ? 1.0 : 0.0);
            q->Q[3 * r_ + c_] = q->Gm[3 * r_ + c_] * q->kb[c_];
            Rb[3 * r_ + c_] = (Sr[3 * r_ + c_] - TQ[3 * c_ + r_]) * q->ks[c_];
            q->Z[3 * r_ + c_] = id + (sc * id - TT[3 * r_ + c_]) * q->ks[c_];
        }
    tru_matmul3(q->SR, q->Si, Rb);
    for (r_ = 0; r_ < 3; r_++)
        for (c_ = 0; c_ < 3; c_++) {
            const double qq = q->Q[3 * r_ + c_];
            q->Z[3 * r_ + 0] -= qq * q->SR[3 * c_ + 0];
            q->Z[3 * r_ + 1] -= qq * q->SR[3 * c_ + 1];
            q->Z[3 * r_ + 2] -= qq * q->SR[3 * c_ + 2];
        }
    return 0;
}

/* (n_b', m_b') of the right-hand side rhs (6) into out (6); -1 if singular.
 * Kirchhoff: S m' = rhs2, n' = rhs1 - G K_bt^-1 m'. */
TR_HOT_INLINE int sys6_solve(const sys6 *q, const double rhs[6], double out[6])
{
    double tmp[3];
    if (q->kirch) {
        double x[3];
        if (solve3(q->S, rhs + 3, x) != 0) return -1;
        {
            const double up[3] = {x[0] * q->kb[0], x[1] * q->kb[1], x[2] * q->kb[2]};
            tru_matvec3(tmp, q->Gm, up);
        }
        out[0] = rhs[0] - tmp[0];
        out[1] = rhs[1] - tmp[1];
        out[2] = rhs[2] - tmp[2];
        out[3] = x[0];
        out[4] = x[1];
        out[5] = x[2];
    } else {
        double Sr2[3], z[3], np_[3];
        int r_, c_;
        tru_matvec3(Sr2, q->Si, rhs + 3);
        for (r_ = 0; r_ < 3; r_++) {
            double zr = rhs[r_];
            for (c_ = 0; c_ < 3; c_++) zr -= q->Q[3 * r_ + c_] * Sr2[c_];
            z[r_] = zr;
        }
        if (solve3(q->Z, z, np_) != 0) return -1;
        tru_matvec3(tmp, q->SR, np_);
        out[0] = np_[0];
        out[1] = np_[1];
        out[2] = np_[2];
        out[3] = Sr2[0] - tmp[0];
        out[4] = Sr2[1] - tmp[1];
        out[5] = Sr2[2] - tmp[2];
    }
    return 0;
}

/* Friction of the nfw frictional taut tendons in fw (TR_FRIC_NCOL columns each, see
 * tr_internal.h): the tendon's load tau t^' = a_i + A_i (v' + u' x r) depends on the
 * solution (n_b', m_b') in out, and the friction load tau' (t^, r x t^) with
 * tau' = -slide mu |tau t^'| enters the right-hand side; fixed-point iteration from the
 * frictionless out.  On return out solves the system with friction and dfric[slot] holds
 * each deficit's rate -tau'.  -1 if singular or not converged. */
static int friction_spatial(const sys6 *q, double *fw, int nfw, double L, const double rhs[6],
                            double out[6], double *dfric, double *gout)
{
    int it, c, k;
    for (c = 0; c < nfw; c++) fw[TR_FRIC_NCOL * c + 12] = 0.0;
    for (it = 0; it < TR_FRIC_ITER; it++) {
        double r6[6], fr[6] = {0, 0, 0, 0, 0, 0};
        const double up[3] = {out[3] * q->kb[0], out[4] * q->kb[1], out[5] * q->kb[2]};
        const double vp[3] = {out[0] * q->ks[0], out[1] * q->ks[1], out[2] * q->ks[2]};
        int done = 1;
        for (c = 0; c < nfw; c++) {
            double *f = fw + TR_FRIC_NCOL * c;
            const double *t = f + 3, *r = f + 6, *a = f + 9;
            /* e = v' + u' x r (r_z = 0), g = a_i + c_t (e - t (t.e)) */
            const double e0 = vp[0] - up[2] * r[1], e1 = vp[1] + up[2] * r[0];
            const double e2 = vp[2] + up[0] * r[1] - up[1] * r[0];
            const double te = t[0] * e0 + t[1] * e1 + t[2] * e2;
            const double g0 = a[0] + f[2] * (e0 - t[0] * te), g1 = a[1] + f[2] * (e1 - t[1] * te);
            const double g2 = a[2] + f[2] * (e2 - t[2] * te);
            const double tp = -f[1] * sqrt(g0 * g0 + g1 * g1 + g2 * g2);
            double *go = gout + 3 * (int)f[0];
            if (fabs(tp - f[12]) > TR_FRIC_TOL * (fabs(tp) + fabs(f[1]) * f[2] / L)) done = 0;
            f[12] = tp;
            go[0] = g0, go[1] = g1, go[2] = g2;
            fr[0] += tp * t[0];
            fr[1] += tp * t[1];
            fr[2] += tp * t[2];
            fr[3] += tp * (r[1] * t[2]);
            fr[4] += tp * (-r[0] * t[2]);
            fr[5] += tp * (r[0] * t[1] - r[1] * t[0]);
        }
        if (done) break; /* out solves the system with these friction loads */
        for (k = 0; k < 6; k++) r6[k] = rhs[k] - fr[k];
        if (sys6_solve(q, r6, out) != 0) return -1;
    }
    if (it == TR_FRIC_ITER) return -1;
    for (c = 0; c < nfw; c++) dfric[(int)fw[TR_FRIC_NCOL * c]] = -fw[TR_FRIC_NCOL * c + 12];
    return 0;
}

/* Per tendon, with t = w/|w|, c_t = tau/|w|, q = r x t (r^ t = q, t^T r^ = -q^T):
 *   A_i = c_t (I - t t^T)            a_i = A_i (u x w + u x r')
 *   A_i r^ = c_t (r^ + t q^T)        G = -sum A_i r^
 *   r^ A_i = c_t (r^ - q t^T)        B = sum r^ A_i
 *   r^ A_i r^ = c_t (r r^T - |r|^2 I + q q^T),  H = -sum r^ A_i r^
 * so the loop accumulates a few scalars and outer products, and the matrices are
 * assembled once.  One function, longer than the house's 120 lines: it is the hot
 * kernel (78 % of a spatial solve's instructions), and its stages share a dozen
 * accumulators that a split would pass through memory. */
TR_HOT_INLINE int rhs_spatial_body(const tr_model *m, const tr_data *d, double s, const double *y,
                                   double *dy, const int gen, const int dyn)
{
    const double *R = y + TR_Y_R, *nb = y + TR_Y_N, *mb = y + TR_Y_M;
    const double *sg = gen ? m->seg_rod + TR_SR_NCOL * d->seg : m->rod_k, *us = sg + TR_SR_U;
    const double EI = sg[TR_SR_EI], GJ = sg[TR_SR_GJ];
    const int kirch = m->kirchhoff, pc = gen && m->precurved;
    /* u - u* = K_bt^-1 m_b */
    double du[3] = {mb[0] / EI, mb[1] / EI, mb[2] / GJ};
    double u[3] = {pc ? du[0] + us[0] : du[0], pc ? du[1] + us[1] : du[1],
                   pc ? du[2] + us[2] : du[2]};
    double v[3] = {0.0, 0.0, 1.0};
    double sc = 0.0, sr2 = 0.0, sr[3] = {0, 0, 0};
    double TT[9] = {0}, TQ[9] = {0}, RR[9] = {0}, QQ[9] = {0};
    double asum[3] = {0}, bsum[3] = {0};
    double rhs[6], tmp[3], tmp2[3];
    int coupled = 0, j, c;
    const int nlen = d->rec ? m->nt : m->ndisp;
    const int a0 = m->seg_act_start[d->seg], a1 = m->seg_act_start[d->seg + 1];
    const int nf = m->nfric, fb = TR_Y_LEN + nlen;
    const double *taus = TR_UNLIKELY(nf) ? fric_tensions(m, d, y) : d->tau;
    double *fw = d->fric_ws;
    int nfw = 0;

    double ev3 = 0.0; /* v3 - 1 */
    if (!kirch) {
        v[0] = nb[0] / sg[TR_SR_GA];
        v[1] = nb[1] / sg[TR_SR_GA];
        ev3 = nb[2] / sg[TR_SR_EA];
        v[2] = 1.0 + ev3;
    }
    if (dyn && tr_dyn_strains(m, d, s, y, sg, us, pc, du, u, v, &ev3) != 0) return GSL_EBADFUNC;
    for (j = 0; j < nlen; j++) dy[TR_Y_LEN + j] = 0.0;
    if (TR_UNLIKELY(nf)) fric_reset(d, nf, dy + TR_Y_LEN + nlen);

    for (c = a0; c < a1; c++) {
        const int i = m->seg_act[c];
        const tr_tendon *td = &m->tendon[i];
        const int lin = !gen || td->route == TR_ROUTE_LINEAR;
        double r0, r1, rp0, rp1, rpp[2] = {0.0, 0.0};
        const double tau = taus[i];
        const int slot = d->rec ? i : td->len_index;
        if (lin) {
            const double rho = td->a * s + td->b;
            r0 = rho * td->cphi;
            r1 = rho * td->sphi;
            rp0 = td->a * td->cphi;
            rp1 = td->a * td->sphi;
        } else {
            double rr[2], rp[2];
            tr_route_eval(m, td, i, d->seg, s, rr, rp, rpp);
            r0 = rr[0];
            r1 = rr[1];
            rp0 = rp[0];
            rp1 = rp[1];
        }
        /* w = v + u x r + r'  (r = (r0, r1, 0)) */
        const double w0 = v[0] - u[2] * r1 + rp0;
        const double w1 = v[1] + u[2] * r0 + rp1;
        const double w2 = v[2] + u[0] * r1 - u[1] * r0;
        const double nw = sqrt(w0 * w0 + w1 * w1 + w2 * w2);
        double t[3], q[3], cv[3], ct, tc, ai[3];
        if (slot >= 0 && !pc && lin) {
            /* |w| - |w_ref|, w_ref = e3 + r': (2 w_ref.dw + |dw|^2) / (|w| + |w_ref|) with
             * dw = (v - e3) + u x r computed directly (no cancellation) */
            const double c = td->wref;
            const double d0 = v[0] - u[2] * r1, d1 = v[1] + u[2] * r0;
            const double d2 = ev3 + u[0] * r1 - u[1] * r0;
            dy[TR_Y_LEN + slot] =
                (2.0 * (rp0 * d0 + rp1 * d1 + d2) + d0 * d0 + d1 * d1 + d2 * d2) / (nw + c);
        } else if (slot >= 0) {
            /* precurved or routed: w_ref = e3 + u* x r + r', dw = (v - e3) + (u - u*) x r */
            const double wr0 = rp0 - us[2] * r1, wr1 = rp1 + us[2] * r0;
            const double wr2 = 1.0 + us[0] * r1 - us[1] * r0;
            const double c = sqrt(wr0 * wr0 + wr1 * wr1 + wr2 * wr2);
            const double d0 = v[0] - du[2] * r1, d1 = v[1] + du[2] * r0;
            const double d2 = ev3 + du[0] * r1 - du[1] * r0;
            dy[TR_Y_LEN + slot] =
                (2.0 * (wr0 * d0 + wr1 * d1 + wr2 * d2) + d0 * d0 + d1 * d1 + d2 * d2) / (nw + c);
        }
        if (TR_UNLIKELY(nf) && td->fric_index >= 0)
            fric_rates(d, i, td, tau, nw, dy + TR_Y_LEN, slot, nlen, nf);
        if (!(tau > 0.0)) continue;
        coupled = 1;
        t[0] = w0 / nw;
        t[1] = w1 / nw;
        t[2] = w2 / nw;
        ct = tau / nw;
        /* q = r x t */
        q[0] = r1 * t[2];
        q[1] = -r0 * t[2];
        q[2] = r0 * t[1] - r1 * t[0];
        /* cv = u x w + u x r' = u x (w + r') */
        {
            const double e0 = w0 + rp0, e1 = w1 + rp1, e2 = w2;
            cv[0] = u[1] * e2 - u[2] * e1;
            cv[1] = u[2] * e0 - u[0] * e2;
            cv[2] = u[0] * e1 - u[1] * e0;
        }
        if (!lin) { /* + r'' */
            cv[0] += rpp[0];
            cv[1] += rpp[1];
        }
        tc = t[0] * cv[0] + t[1] * cv[1] + t[2] * cv[2];
        ai[0] = ct * (cv[0] - t[0] * tc);
        ai[1] = ct * (cv[1] - t[1] * tc);
        ai[2] = ct * (cv[2] - t[2] * tc);
        if (TR_UNLIKELY(nf) && td->fric_index >= 0) {
            const double rr[3] = {r0, r1, 0.0};
            fric_record(fw + TR_FRIC_NCOL * nfw++, d, td, ct, t, rr, ai);
        }
        asum[0] += ai[0];
        asum[1] += ai[1];
        asum[2] += ai[2];
        /* b_i = r x a_i */
        bsum[0] += r1 * ai[2];
        bsum[1] += -r0 * ai[2];
        bsum[2] += r0 * ai[1] - r1 * ai[0];
        sc += ct;
        sr[0] += ct * r0;
        sr[1] += ct * r1;
        sr2 += ct * (r0 * r0 + r1 * r1);
        RR[0] += ct * r0 * r0;
        RR[1] += ct * r0 * r1;
        RR[4] += ct * r1 * r1;
        {
            int p_, k_;
            for (p_ = 0; p_ < 3; p_++) {
                const double ctp = ct * t[p_], cqp = ct * q[p_];
                for (k_ = 0; k_ < 3; k_++) {
                    TQ[3 * p_ + k_] += ctp * q[k_];
                    QQ[3 * p_ + k_] += cqp * q[k_];
                }
                if (!kirch) /* A = sc I - TT enters the Cosserat system only */
                    for (k_ = 0; k_ < 3; k_++) TT[3 * p_ + k_] += ctp * t[k_];
            }
        }
    }

    /* right-hand sides */
    tru_cross3(tmp, u, nb);
    rhs[0] = -tmp[0] - asum[0];
    rhs[1] = -tmp[1] - asum[1];
    rhs[2] = -tmp[2] - asum[2];
    if (m->has_dist) {
        const double lam = d->lam_load;
        const double fw[3] = {lam * m->dist[0], lam * m->dist[1], lam * m->dist[2]};
        tru_mattvec3(tmp, R, fw);
        rhs[0] -= tmp[0];
        rhs[1] -= tmp[1];
        rhs[2] -= tmp[2];
    }
    if (m->has_pdist) {
        const double lam = d->lam_load, *f = m->seg_pdist + 3 * d->seg;
        const double fw[3] = {lam * f[0], lam * f[1], lam * f[2]};
        tru_mattvec3(tmp, R, fw);
        rhs[0] -= tmp[0];
        rhs[1] -= tmp[1];
        rhs[2] -= tmp[2];
    }
    tru_cross3(tmp, u, mb);
    tru_cross3(tmp2, v, nb);
    rhs[3] = -tmp[0] - tmp2[0] - bsum[0];
    rhs[4] = -tmp[1] - tmp2[1] - bsum[1];
    rhs[5] = -tmp[2] - tmp2[2] - bsum[2];
    if (dyn) tr_dyn_loads(d, y, sg, coupled, rhs, sc, sr, sr2, RR, TQ, QQ, TT);

    if (!coupled) {
        memcpy(dy + TR_Y_N, rhs, 6 * sizeof(double));
    } else {
        sys6 q;
        double out[6];
        q.kirch = kirch;
        q.kb[0] = 1.0 / EI;
        q.kb[1] = 1.0 / EI;
        q.kb[2] = 1.0 / GJ;
        if (kirch) {
            q.ks[0] = q.ks[1] = q.ks[2] = 0.0;
        } else {
            q.ks[0] = q.ks[1] = 1.0 / sg[TR_SR_GA];
            q.ks[2] = 1.0 / sg[TR_SR_EA];
        }
        RR[3] = RR[1];
        if (dyn) { /* K^-1 / (1 + eta c0): the viscous part */
            const double fd = 1.0 / (1.0 + d->dyn->eta * d->dyn->c0);
            for (j = 0; j < 3; j++) {
                q.kb[j] *= fd;
                q.ks[j] *= fd;
            }
        }
        if (sys6_setup(&q, sr, sr2, sc, RR, TQ, QQ, TT) != 0 || sys6_solve(&q, rhs, out) != 0)
            return GSL_EBADFUNC;
        /* a friction iteration that does not settle (a trial state of an adaptive step far
         * off the solution) asks the adaptive integrator for a smaller step */
        if (TR_UNLIKELY(nfw > 0)) {
            sys6 qf = q; /* as in rhs_planar */
            if (friction_spatial(&qf, fw, nfw, m->L, rhs, out, dy + fb, d->fric_g) != 0)
                return GSL_FAILURE;
        }
        memcpy(dy + TR_Y_N, out, 6 * sizeof(double));
    }

    if (dyn) tr_dyn_store(d, dy, sg);
    /* kinematics: p' = R v, R' = R u^  (row j of R u^ = R_j x u) */
    tru_matvec3(dy + TR_Y_P, R, v);
    for (j = 0; j < 3; j++) tru_cross3(dy + TR_Y_R + 3 * j, R + 3 * j, u);
    return GSL_SUCCESS;
}

/* The kernel compiled twice: the static one (dyn = 0: the hooks of a time step compiled
 * out, the kernel as it was before the dynamics, bench/compare_instructions.py) and the
 * one of a time step of the dynamics (tr_dyn_rhs.c), which reads the general rigidities. */
static int rhs_spatial(const tr_model *m, const tr_data *d, double s, const double *y, double *dy,
                       const int gen)
{
    return rhs_spatial_body(m, d, s, y, dy, gen, 0);
}

static int rhs_spatial_dyn(const tr_model *m, const tr_data *d, double s, const double *y,
                           double *dy)
{
    return rhs_spatial_body(m, d, s, y, dy, 1, 1);
}

/* -------------------------------------------------------------- planar */
/* The planar system in (n1', n3', m2') of one evaluation: Kirchhoff, one division
 * (1 + H/EI) m2' = r2 and n' = r - G m2'/EI; Cosserat, the 3 x 3 matrix M3. */
typedef struct {
    int kirch;
    double EI, H, G1, G3, ks1, ks3, M3[9];
} sys3;

TR_HOT_INLINE int sys3_solve(sys3 *q, const double rr[3], double out[3], int keep)
{
    if (q->kirch) {
        const double mp = rr[2] / (1.0 + q->H / q->EI);
        out[2] = mp;
        out[0] = rr[0] - q->G1 * mp / q->EI;
        out[1] = rr[1] - q->G3 * mp / q->EI;
        return 0;
    } else {
        /* the elimination overwrites its matrix: on a copy when it is solved again */
        double M3[9], *M = q->M3;
        if (keep) M = memcpy(M3, q->M3, sizeof M3);
        out[0] = rr[0];
        out[1] = rr[1];
        out[2] = rr[2];
        return tru_solve_dense(3, M, out) != 0 ? -1 : 0;
    }
}

/* friction_spatial in the x-z plane: e = (v1', v3' - kap' rho), the friction force
 * tau' (t1, t3) and its moment about y, -rho tau' t3. */
static int friction_planar(sys3 *q, double *fw, int nfw, double L, const double rr[3],
                           double out[3], double *dfric, double *gout)
{
    int it, c;
    for (c = 0; c < nfw; c++) fw[TR_FRIC_NCOL * c + 12] = 0.0;
    for (it = 0; it < TR_FRIC_ITER; it++) {
        const double v1p = out[0] * q->ks1, v3p = out[1] * q->ks3, kp = out[2] / q->EI;
        double fr[3] = {0, 0, 0}, r3[3];
        int done = 1;
        for (c = 0; c < nfw; c++) {
            double *f = fw + TR_FRIC_NCOL * c;
            const double t1 = f[3], t3 = f[5], rho = f[6];
            const double e1 = v1p, e3 = v3p - kp * rho, te = t1 * e1 + t3 * e3;
            const double g1 = f[9] + f[2] * (e1 - t1 * te), g3 = f[11] + f[2] * (e3 - t3 * te);
            const double tp = -f[1] * sqrt(g1 * g1 + g3 * g3);
            double *go = gout + 3 * (int)f[0];
            if (fabs(tp - f[12]) > TR_FRIC_TOL * (fabs(tp) + fabs(f[1]) * f[2] / L)) done = 0;
            f[12] = tp;
            go[0] = g1, go[1] = 0.0, go[2] = g3;
            fr[0] += tp * t1;
            fr[1] += tp * t3;
            fr[2] += -rho * tp * t3;
        }
        if (done) break; /* out solves the system with these friction loads */
        for (c = 0; c < 3; c++) r3[c] = rr[c] - fr[c];
        if (sys3_solve(q, r3, out, 1) != 0) return -1;
    }
    if (it == TR_FRIC_ITER) return -1;
    for (c = 0; c < nfw; c++) dfric[(int)fw[TR_FRIC_NCOL * c]] = -fw[TR_FRIC_NCOL * c + 12];
    return 0;
}

/* x-z plane, rotation about +y by theta: R = [[c,0,s],[0,1,0],[-s,0,c]].
 * Body vectors (x, z) components, moments about y; tendon offset rho e_x.  Longer than the
 * house's 120 lines for the reason rhs_spatial is: the hot kernel's accumulators. */
TR_HOT_INLINE int rhs_planar_body(const tr_model *m, const tr_data *d, double s, const double *y,
                                  double *dy, const int gen, const int fric)
{
    const double th = y[TR_YP_TH], n1 = y[TR_YP_N1], n3 = y[TR_YP_N3], m2 = y[TR_YP_M];
    const double *sr = gen ? m->seg_rod + TR_SR_NCOL * d->seg : m->rod_k;
    const double EI = sr[TR_SR_EI];
    const int kirch = m->kirchhoff;
    /* kap - kap* = m2 / EI (kap* = 0 but on a precurved section) */
    const double dkap = m2 / EI, kap = gen ? dkap + sr[TR_SR_U + 1] : dkap;
    const double ct = cos(th), st = sin(th);
    double v1 = 0.0, v3 = 1.0;
    double A11 = 0, A13 = 0, A33 = 0, G1 = 0, G3 = 0, B1 = 0, B3 = 0, H = 0;
    double a1s = 0, a3s = 0, bs = 0;
    int coupled = 0, j, c;
    const int nlen = d->rec ? m->nt : m->ndisp;
    const int c0 = m->seg_act_start[d->seg], c1 = m->seg_act_start[d->seg + 1];
    const int nf = fric ? m->nfric : 0;
    const double *taus = TR_UNLIKELY(nf) ? fric_tensions(m, d, y) : d->tau;
    double *fw = d->fric_ws;
    int nfw = 0;
    double r1, r3, r2;

    double ev3 = 0.0; /* v3 - 1 */
    if (!kirch) {
        v1 = n1 / sr[TR_SR_GA];
        ev3 = n3 / sr[TR_SR_EA];
        v3 = 1.0 + ev3;
    }
    for (j = 0; j < nlen; j++) dy[TR_YP_LEN + j] = 0.0;
    if (TR_UNLIKELY(nf)) fric_reset(d, nf, dy + TR_YP_LEN + nlen);

    for (c = c0; c < c1; c++) {
        const int i = m->seg_act[c];
        const tr_tendon *td = &m->tendon[i];
        const double rho = td->cphi * (td->a * s + td->b);
        const double rp = td->cphi * td->a;
        const double w1 = v1 + rp, w3 = v3 - kap * rho;
        const double nw = sqrt(w1 * w1 + w3 * w3);
        const double tau = taus[i];
        const int slot = d->rec ? i : td->len_index;
        if (slot >= 0 && !gen) {
            /* |w| - |w_ref| without cancellation (see rhs_spatial) */
            /* (rp^2 = a^2: cphi is exactly +-1 in a planar model) */
            const double c = td->wref, d1 = v1, d3 = ev3 - kap * rho;
            dy[TR_YP_LEN + slot] = (2.0 * (rp * d1 + d3) + d1 * d1 + d3 * d3) / (nw + c);
        } else if (slot >= 0) {
            /* sections: w_ref = (r', 1 - kap* rho), dw = (v1, v3 - 1 - (kap - kap*) rho) */
            const double wr3 = 1.0 - sr[TR_SR_U + 1] * rho, c = sqrt(rp * rp + wr3 * wr3);
            const double d1 = v1, d3 = ev3 - dkap * rho;
            dy[TR_YP_LEN + slot] = (2.0 * (rp * d1 + wr3 * d3) + d1 * d1 + d3 * d3) / (nw + c);
        }
        if (TR_UNLIKELY(nf) && td->fric_index >= 0)
            fric_rates(d, i, td, tau, nw, dy + TR_YP_LEN, slot, nlen, nf);
        if (!(tau > 0.0)) continue;
        coupled = 1;
        {
            const double cf = tau / (nw * nw * nw);
            const double a11 = cf * w3 * w3, a13 = -cf * w1 * w3, a33 = cf * w1 * w1;
            /* c = u x w + u x r' = (kap w3, -kap (w1 + r')) */
            const double cv1 = kap * w3, cv3 = -kap * (w1 + rp);
            const double ai1 = a11 * cv1 + a13 * cv3, ai3 = a13 * cv1 + a33 * cv3;
            if (TR_UNLIKELY(nf) && td->fric_index >= 0) {
                const double t[3] = {w1 / nw, 0.0, w3 / nw}, rr[3] = {rho, 0.0, 0.0};
                const double ai[3] = {ai1, 0.0, ai3};
                fric_record(fw + TR_FRIC_NCOL * nfw++, d, td, tau / nw, t, rr, ai);
            }
            a1s += ai1;
            a3s += ai3;
            bs += -rho * ai3;
            G1 += -rho * a13;
            G3 += -rho * a33;
            H += rho * rho * a33;
            if (!kirch) {
                A11 += a11;
                A13 += a13;
                A33 += a33;
                B1 += -rho * a13;
                B3 += -rho * a33;
            }
        }
    }
    /* rhs1 = -u x n - a - f_e,  u x n = (kap n3, -kap n1);  rhs2 = -(v x n)_y - b */
    r1 = -kap * n3 - a1s;
    r3 = kap * n1 - a3s;
    if (m->has_dist) {
        const double lam = d->lam_load;
        const double fx = lam * m->dist[0], fz = lam * m->dist[2];
        r1 -= ct * fx - st * fz;
        r3 -= st * fx + ct * fz;
    }
    if (m->has_pdist) {
        const double lam = d->lam_load, *f = m->seg_pdist + 3 * d->seg;
        const double fx = lam * f[0], fz = lam * f[2];
        r1 -= ct * fx - st * fz;
        r3 -= st * fx + ct * fz;
    }
    r2 = -(v3 * n1 - v1 * n3) - bs;

    if (!coupled) {
        dy[TR_YP_N1] = r1;
        dy[TR_YP_N3] = r3;
        dy[TR_YP_M] = r2;
    } else {
        sys3 q;
        const double rr[3] = {r1, r3, r2};
        double out[3];
        q.kirch = kirch;
        q.EI = EI;
        q.H = H;
        q.G1 = G1;
        q.G3 = G3;
        q.ks1 = kirch ? 0.0 : 1.0 / sr[TR_SR_GA];
        q.ks3 = kirch ? 0.0 : 1.0 / sr[TR_SR_EA];
        if (!kirch) {
            const double kb = 1.0 / EI;
            q.M3[0] = 1.0 + A11 * q.ks1, q.M3[1] = A13 * q.ks3, q.M3[2] = G1 * kb;
            q.M3[3] = A13 * q.ks1, q.M3[4] = 1.0 + A33 * q.ks3, q.M3[5] = G3 * kb;
            q.M3[6] = B1 * q.ks1, q.M3[7] = B3 * q.ks3, q.M3[8] = 1.0 + H * kb;
        }
        if (sys3_solve(&q, rr, out, nfw > 0) != 0) return GSL_EBADFUNC;
        if (TR_UNLIKELY(nfw > 0)) {
            sys3 qf = q; /* a copy: q itself stays in registers on the frictionless path */
            if (friction_planar(&qf, fw, nfw, m->L, rr, out, dy + TR_YP_LEN + nlen, d->fric_g) != 0)
                return GSL_FAILURE; /* as in rhs_spatial */
        }
        dy[TR_YP_N1] = out[0];
        dy[TR_YP_N3] = out[1];
        dy[TR_YP_M] = out[2];
    }
    dy[TR_YP_X] = ct * v1 + st * v3;
    dy[TR_YP_Z] = -st * v1 + ct * v3;
    dy[TR_YP_TH] = kap;
    return GSL_SUCCESS;
}

/* The planar kernel compiled twice, without and with friction: the frictionless one is the
 * kernel as it was before friction (bench/compare_instructions.py). */
static int rhs_planar(const tr_model *m, const tr_data *d, double s, const double *y, double *dy,
                      const int gen)
{
    return rhs_planar_body(m, d, s, y, dy, gen, 0);
}

static int rhs_planar_fric(const tr_model *m, const tr_data *d, double s, const double *y,
                           double *dy, const int gen)
{
    return rhs_planar_body(m, d, s, y, dy, gen, 1);
}

int tr_rhs(double s, const double y[], double dyds[], void *params)
{
    tr_data *d = (tr_data *)params;
    const tr_model *m = d->vm;
    d->spent += m->rhs_work;
    if (m->planar)
        return m->nfric     ? rhs_planar_fric(m, d, s, y, dyds, m->general)
               : m->general ? rhs_planar(m, d, s, y, dyds, 1)
                            : rhs_planar(m, d, s, y, dyds, 0);
    if (TR_UNLIKELY(d->dyn != NULL)) /* a time step of the dynamics (tr_dyn.c) */
        return rhs_spatial_dyn(m, d, s, y, dyds);
    return m->general ? rhs_spatial(m, d, s, y, dyds, 1) : rhs_spatial(m, d, s, y, dyds, 0);
}
