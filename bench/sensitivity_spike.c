/*
 * sensitivity_spike.c -- a prototype, not part of the solver: the cost of forward
 * sensitivities of the spatial right-hand side, for a go/no-go decision on variational
 * equations integrated with the state.
 *
 * The core's kernel rhs_spatial_body is static in csrc/tr_rod.c, so this file includes
 * tr_rod.c (its tr_rhs renamed) and links every other core file.  Its own tr_rhs records
 * the states of one shooting pass at a solved scene, then forwards to the core's.
 *
 * rhs_tangent: the right-hand side and its tangent along k directions at once (seeds on
 * the state y and on the tensions tau), hand-derived, for the simplest formulation only:
 * spatial, static, uniform straight rod with linear tendons (gen = 0), no friction, taut
 * tendons stay taut and slack ones slack (no switching: the kink is not differentiated).
 *
 * Reads one scene in bench/solve_harness.c's text format (only load set 0 is used) and
 *   1. solves it cold, re-evaluates the residual at the solution and keeps the states of
 *      that pass (every right-hand side call: the rk8pd stages along s);
 *   2. checks the tangent against central differences of the core's kernel (Richardson-
 *      extrapolated) along k random directions, per state block;
 *   3. times, interleaved, the kernel alone and the kernel + tangent for k = 1 and k = 9
 *      (thread CPU time, medians of `blocks` blocks of 20 passes over the states), and
 *      GSL's rk8pd step on n and n (1 + k) states with a trivial right-hand side (the
 *      stepper's vector work that a variational state would multiply);
 *   4. times default cold solves (compile + tr_solve + free, with and without the verdict)
 *      and counts their right-hand side calls, nfev and njev.
 * A third argument N replaces step 4 by N default cold solves (for perf record; blocks = 3),
 * the first printing the right-hand side calls of each of its shooting passes.
 *
 *   gcc $(grep -v '^#' csrc/CFLAGS) -D_POSIX_C_SOURCE=200809L -Icsrc $(pkg-config --cflags gsl) \
 *       bench/sensitivity_spike.c $(ls csrc/tr_*.c | grep -v tr_rod.c) \
 *       -o /tmp/sensitivity_spike $(pkg-config --libs gsl) -lm
 *   /tmp/sensitivity_spike [blocks=201 [seed=1e-3 [N]]] < scene.txt
 */
#define tr_rhs tr_rhs_core
#include "../csrc/tr_rod.c"
#undef tr_rhs

#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include <gsl/gsl_odeiv2.h>

int tr_rhs(double s, const double y[], double dyds[], void *params);

#define KMAX  9
#define NTMAX 16
#define NSMAX 4096
#define YMAX  64

/* ------------------------------------------------------------ captured states */
typedef struct {
    long calls, mark; /* every right-hand side call; the count at the last pass's start */
    int on, n, ny;    /* on: 1 keep the states, 2 print each shooting pass's call count */
    double s[NSMAX], y[NSMAX][YMAX];
    int seg[NSMAX];
} capture_buf;

static capture_buf cap; /* a prototype's recorder: one solve at a time */

int tr_rhs(double s, const double y[], double dyds[], void *params)
{
    const tr_data *d = (const tr_data *)params;
    if (cap.on == 2 && s == 0.0 && !d->rec) { /* a shooting pass starts at s = 0 */
        if (cap.calls > cap.mark) printf(" %ld", cap.calls - cap.mark);
        cap.mark = cap.calls;
    }
    cap.calls++;
    if (cap.on == 1 && cap.n < NSMAX && !d->rec && cap.ny <= YMAX) {
        cap.s[cap.n] = s;
        cap.seg[cap.n] = d->seg;
        memcpy(cap.y[cap.n], y, (size_t)cap.ny * sizeof(double));
        cap.n++;
    }
    return tr_rhs_core(s, y, dyds, params);
}

/* ------------------------------------------------------------ the tangent */
#define FOR_K for (i = 0; i < k; i++)

/* dy = f(y) as rhs_spatial_body(gen = 0, dyn = 0) computes it, and dY = f'(y) Y +
 * f_tau dtau for k directions.  Tangent layout: component-major, Y[c k + i] the i-th
 * direction's component c (n_states components); dtau[j k + i] tendon j's.  -1 if the
 * model is outside this prototype's formulation or the system is singular. */
TR_HOT_INLINE int rhs_tangent_body(const tr_model *m, const tr_data *d, double s, const double *y,
                                   const double *Y, const double *dtau, double *dy, double *dY,
                                   const int k)
{
    const double *R = y + TR_Y_R, *nb = y + TR_Y_N, *mb = y + TR_Y_M;
    const double *dR = Y + TR_Y_R * k, *dn = Y + TR_Y_N * k, *dm = Y + TR_Y_M * k;
    const double *sg = m->rod_k;
    const double EI = sg[TR_SR_EI], GJ = sg[TR_SR_GJ];
    const int kirch = m->kirchhoff;
    const double kb[3] = {1.0 / EI, 1.0 / EI, 1.0 / GJ};
    double ks[3] = {0.0, 0.0, 0.0};
    double u[3] = {mb[0] / EI, mb[1] / EI, mb[2] / GJ}, v[3] = {0.0, 0.0, 1.0}, ev3 = 0.0;
    double du[3][KMAX], dv[3][KMAX];
    double sc = 0.0, sr2 = 0.0, sr[3] = {0, 0, 0};
    double TT[9] = {0}, TQ[9] = {0}, RR[9] = {0}, QQ[9] = {0};
    double asum[3] = {0}, bsum[3] = {0}, dasum[3][KMAX], dbsum[3][KMAX];
    double rhs[6], drhs[6][KMAX], tmp[3], tmp2[3];
    /* the taut tendons' t, c_t, r and their tangents, for the system's tangent */
    double tt[NTMAX][3], ctt[NTMAX], rt[NTMAX][2], dtt[NTMAX][3][KMAX], dctt[NTMAX][KMAX];
    int ntaut = 0, j, c, i;
    const int nlen = m->ndisp;
    const int a0 = m->seg_act_start[d->seg], a1 = m->seg_act_start[d->seg + 1];

    if (m->general || m->nfric || m->precurved || d->rec || m->has_pdist) return -1;
    if (!kirch) {
        ks[0] = ks[1] = 1.0 / sg[TR_SR_GA];
        ks[2] = 1.0 / sg[TR_SR_EA];
        v[0] = nb[0] * ks[0];
        v[1] = nb[1] * ks[1];
        ev3 = nb[2] * ks[2];
        v[2] = 1.0 + ev3;
    }
    for (c = 0; c < 3; c++) FOR_K
        {
            du[c][i] = dm[c * k + i] * kb[c];
            dv[c][i] = dn[c * k + i] * ks[c];
            dasum[c][i] = dbsum[c][i] = 0.0;
        }
    for (j = 0; j < nlen; j++) {
        dy[TR_Y_LEN + j] = 0.0;
        FOR_K dY[(TR_Y_LEN + j) * k + i] = 0.0;
    }

    for (c = a0; c < a1; c++) {
        const int ti = m->seg_act[c];
        const tr_tendon *td = &m->tendon[ti];
        const double tau = d->tau[ti];
        const int slot = td->len_index;
        const double rho = td->a * s + td->b;
        const double r0 = rho * td->cphi, r1 = rho * td->sphi;
        const double rp0 = td->a * td->cphi, rp1 = td->a * td->sphi;
        const double w0 = v[0] - u[2] * r1 + rp0;
        const double w1 = v[1] + u[2] * r0 + rp1;
        const double w2 = v[2] + u[0] * r1 - u[1] * r0;
        const double nw = sqrt(w0 * w0 + w1 * w1 + w2 * w2), inw = 1.0 / nw;
        double dw[3][KMAX], dnw[KMAX];
        double t[3], q[3], cv[3], ct, tc, ai[3], pa[3];
        FOR_K
        {
            dw[0][i] = dv[0][i] - du[2][i] * r1;
            dw[1][i] = dv[1][i] + du[2][i] * r0;
            dw[2][i] = dv[2][i] + du[0][i] * r1 - du[1][i] * r0;
            dnw[i] = (w0 * dw[0][i] + w1 * dw[1][i] + w2 * dw[2][i]) * inw;
        }
        if (slot >= 0) {
            const double cw = td->wref;
            const double d0 = v[0] - u[2] * r1, d1 = v[1] + u[2] * r0;
            const double d2 = ev3 + u[0] * r1 - u[1] * r0;
            dy[TR_Y_LEN + slot] =
                (2.0 * (rp0 * d0 + rp1 * d1 + d2) + d0 * d0 + d1 * d1 + d2 * d2) / (nw + cw);
            FOR_K dY[(TR_Y_LEN + slot) * k + i] = dnw[i]; /* |w| - |w_ref| */
        }
        if (!(tau > 0.0)) continue;
        t[0] = w0 * inw;
        t[1] = w1 * inw;
        t[2] = w2 * inw;
        ct = tau * inw;
        q[0] = r1 * t[2];
        q[1] = -r0 * t[2];
        q[2] = r0 * t[1] - r1 * t[0];
        {
            const double e0 = w0 + rp0, e1 = w1 + rp1, e2 = w2;
            cv[0] = u[1] * e2 - u[2] * e1;
            cv[1] = u[2] * e0 - u[0] * e2;
            cv[2] = u[0] * e1 - u[1] * e0;
            tc = t[0] * cv[0] + t[1] * cv[1] + t[2] * cv[2];
            pa[0] = cv[0] - t[0] * tc;
            pa[1] = cv[1] - t[1] * tc;
            pa[2] = cv[2] - t[2] * tc;
            ai[0] = ct * pa[0];
            ai[1] = ct * pa[1];
            ai[2] = ct * pa[2];
            FOR_K
            {
                /* t' = (w' - t |w|') / |w|,  c_t' = (tau' - c_t |w|') / |w|,
                 * cv' = u' x e + u x w',  a_i' = c_t' (cv - t tc) + c_t (cv' - t' tc - t tc') */
                const double dt0 = (dw[0][i] - t[0] * dnw[i]) * inw;
                const double dt1 = (dw[1][i] - t[1] * dnw[i]) * inw;
                const double dt2 = (dw[2][i] - t[2] * dnw[i]) * inw;
                const double dct = (dtau[ti * k + i] - ct * dnw[i]) * inw;
                const double dc0 =
                    du[1][i] * e2 - du[2][i] * e1 + u[1] * dw[2][i] - u[2] * dw[1][i];
                const double dc1 =
                    du[2][i] * e0 - du[0][i] * e2 + u[2] * dw[0][i] - u[0] * dw[2][i];
                const double dc2 =
                    du[0][i] * e1 - du[1][i] * e0 + u[0] * dw[1][i] - u[1] * dw[0][i];
                const double dtc =
                    dt0 * cv[0] + dt1 * cv[1] + dt2 * cv[2] + t[0] * dc0 + t[1] * dc1 + t[2] * dc2;
                const double da0 = dct * pa[0] + ct * (dc0 - dt0 * tc - t[0] * dtc);
                const double da1 = dct * pa[1] + ct * (dc1 - dt1 * tc - t[1] * dtc);
                const double da2 = dct * pa[2] + ct * (dc2 - dt2 * tc - t[2] * dtc);
                dasum[0][i] += da0;
                dasum[1][i] += da1;
                dasum[2][i] += da2;
                dbsum[0][i] += r1 * da2;
                dbsum[1][i] += -r0 * da2;
                dbsum[2][i] += r0 * da1 - r1 * da0;
                dtt[ntaut][0][i] = dt0;
                dtt[ntaut][1][i] = dt1;
                dtt[ntaut][2][i] = dt2;
                dctt[ntaut][i] = dct;
            }
        }
        memcpy(tt[ntaut], t, sizeof t);
        ctt[ntaut] = ct;
        rt[ntaut][0] = r0;
        rt[ntaut][1] = r1;
        ntaut++;
        asum[0] += ai[0];
        asum[1] += ai[1];
        asum[2] += ai[2];
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
                if (!kirch)
                    for (k_ = 0; k_ < 3; k_++) TT[3 * p_ + k_] += ctp * t[k_];
            }
        }
    }

    /* right-hand sides and their tangents */
    tru_cross3(tmp, u, nb);
    rhs[0] = -tmp[0] - asum[0];
    rhs[1] = -tmp[1] - asum[1];
    rhs[2] = -tmp[2] - asum[2];
    FOR_K
    {
        drhs[0][i] =
            -(du[1][i] * nb[2] - du[2][i] * nb[1] + u[1] * dn[2 * k + i] - u[2] * dn[1 * k + i]) -
            dasum[0][i];
        drhs[1][i] =
            -(du[2][i] * nb[0] - du[0][i] * nb[2] + u[2] * dn[0 * k + i] - u[0] * dn[2 * k + i]) -
            dasum[1][i];
        drhs[2][i] =
            -(du[0][i] * nb[1] - du[1][i] * nb[0] + u[0] * dn[1 * k + i] - u[1] * dn[0 * k + i]) -
            dasum[2][i];
    }
    if (m->has_dist) {
        const double lam = d->lam_load;
        const double fw[3] = {lam * m->dist[0], lam * m->dist[1], lam * m->dist[2]};
        tru_mattvec3(tmp, R, fw);
        for (c = 0; c < 3; c++) {
            rhs[c] -= tmp[c];
            FOR_K drhs[c][i] -= dR[(0 + c) * k + i] * fw[0] + dR[(3 + c) * k + i] * fw[1] +
                                dR[(6 + c) * k + i] * fw[2];
        }
    }
    tru_cross3(tmp, u, mb);
    tru_cross3(tmp2, v, nb);
    rhs[3] = -tmp[0] - tmp2[0] - bsum[0];
    rhs[4] = -tmp[1] - tmp2[1] - bsum[1];
    rhs[5] = -tmp[2] - tmp2[2] - bsum[2];
    FOR_K
    {
        drhs[3][i] =
            -(du[1][i] * mb[2] - du[2][i] * mb[1] + u[1] * dm[2 * k + i] - u[2] * dm[1 * k + i]) -
            (dv[1][i] * nb[2] - dv[2][i] * nb[1] + v[1] * dn[2 * k + i] - v[2] * dn[1 * k + i]) -
            dbsum[0][i];
        drhs[4][i] =
            -(du[2][i] * mb[0] - du[0][i] * mb[2] + u[2] * dm[0 * k + i] - u[0] * dm[2 * k + i]) -
            (dv[2][i] * nb[0] - dv[0][i] * nb[2] + v[2] * dn[0 * k + i] - v[0] * dn[2 * k + i]) -
            dbsum[1][i];
        drhs[5][i] =
            -(du[0][i] * mb[1] - du[1][i] * mb[0] + u[0] * dm[1 * k + i] - u[1] * dm[0 * k + i]) -
            (dv[0][i] * nb[1] - dv[1][i] * nb[0] + v[0] * dn[1 * k + i] - v[1] * dn[0 * k + i]) -
            dbsum[2][i];
    }

    if (ntaut == 0) {
        memcpy(dy + TR_Y_N, rhs, 6 * sizeof(double));
        for (c = 0; c < 6; c++) FOR_K dY[(TR_Y_N + c) * k + i] = drhs[c][i];
    } else {
        sys6 qs;
        double out[6], Zi[9], vp[3], up[3];
        int t_;
        qs.kirch = kirch;
        memcpy(qs.kb, kb, sizeof kb);
        memcpy(qs.ks, ks, sizeof ks);
        RR[3] = RR[1];
        if (sys6_setup(&qs, sr, sr2, sc, RR, TQ, QQ, TT) != 0 || sys6_solve(&qs, rhs, out) != 0)
            return -1;
        memcpy(dy + TR_Y_N, out, 6 * sizeof(double));
        /* M(y) out = rhs: M out' = rhs' - M' out, M' out = sum_i (A_i' e_i, r_i x A_i' e_i)
         * with e_i = v' + u' x r_i (the tendon's strain rate at the solution) and
         * A_i' e = c_t' (e - t (t.e)) - c_t (t' (t.e) + t (t'.e)) */
        for (c = 0; c < 3; c++) {
            vp[c] = out[c] * ks[c];
            up[c] = out[3 + c] * kb[c];
        }
        for (t_ = 0; t_ < ntaut; t_++) {
            const double *t = tt[t_], ct = ctt[t_], r0 = rt[t_][0], r1 = rt[t_][1];
            const double e0 = vp[0] - up[2] * r1, e1 = vp[1] + up[2] * r0;
            const double e2 = vp[2] + up[0] * r1 - up[1] * r0;
            const double te = t[0] * e0 + t[1] * e1 + t[2] * e2;
            const double pe0 = e0 - t[0] * te, pe1 = e1 - t[1] * te, pe2 = e2 - t[2] * te;
            FOR_K
            {
                const double dt0 = dtt[t_][0][i], dt1 = dtt[t_][1][i], dt2 = dtt[t_][2][i];
                const double dte = dt0 * e0 + dt1 * e1 + dt2 * e2, dct = dctt[t_][i];
                const double f0 = dct * pe0 - ct * (dt0 * te + t[0] * dte);
                const double f1 = dct * pe1 - ct * (dt1 * te + t[1] * dte);
                const double f2 = dct * pe2 - ct * (dt2 * te + t[2] * dte);
                drhs[0][i] -= f0;
                drhs[1][i] -= f1;
                drhs[2][i] -= f2;
                drhs[3][i] -= r1 * f2;
                drhs[4][i] -= -r0 * f2;
                drhs[5][i] -= r0 * f1 - r1 * f0;
            }
        }
        if (kirch) {
            /* S m' = rhs_m, n' = rhs_n - G K_bt^-1 m' */
            if (inv3(qs.S, qs.Si) != 0) return -1;
            FOR_K
            {
                double x[3], g[3];
                for (c = 0; c < 3; c++)
                    x[c] = qs.Si[3 * c] * drhs[3][i] + qs.Si[3 * c + 1] * drhs[4][i] +
                           qs.Si[3 * c + 2] * drhs[5][i];
                for (c = 0; c < 3; c++)
                    g[c] = qs.Gm[3 * c] * x[0] * kb[0] + qs.Gm[3 * c + 1] * x[1] * kb[1] +
                           qs.Gm[3 * c + 2] * x[2] * kb[2];
                for (c = 0; c < 3; c++) {
                    dY[(TR_Y_N + c) * k + i] = drhs[c][i] - g[c];
                    dY[(TR_Y_M + c) * k + i] = x[c];
                }
            }
        } else {
            if (inv3(qs.Z, Zi) != 0) return -1;
            FOR_K
            {
                double s2[3], z[3], np_[3];
                for (c = 0; c < 3; c++)
                    s2[c] = qs.Si[3 * c] * drhs[3][i] + qs.Si[3 * c + 1] * drhs[4][i] +
                            qs.Si[3 * c + 2] * drhs[5][i];
                for (c = 0; c < 3; c++)
                    z[c] = drhs[c][i] - qs.Q[3 * c] * s2[0] - qs.Q[3 * c + 1] * s2[1] -
                           qs.Q[3 * c + 2] * s2[2];
                for (c = 0; c < 3; c++)
                    np_[c] = Zi[3 * c] * z[0] + Zi[3 * c + 1] * z[1] + Zi[3 * c + 2] * z[2];
                for (c = 0; c < 3; c++) {
                    dY[(TR_Y_N + c) * k + i] = np_[c];
                    dY[(TR_Y_M + c) * k + i] = s2[c] - qs.SR[3 * c] * np_[0] -
                                               qs.SR[3 * c + 1] * np_[1] -
                                               qs.SR[3 * c + 2] * np_[2];
                }
            }
        }
    }

    /* kinematics: p' = R v, R_j' = R_j x u */
    tru_matvec3(dy + TR_Y_P, R, v);
    for (j = 0; j < 3; j++) tru_cross3(dy + TR_Y_R + 3 * j, R + 3 * j, u);
    for (c = 0; c < 3; c++) FOR_K
        {
            dY[(TR_Y_P + c) * k + i] = dR[(3 * c) * k + i] * v[0] + dR[(3 * c + 1) * k + i] * v[1] +
                                       dR[(3 * c + 2) * k + i] * v[2] + R[3 * c] * dv[0][i] +
                                       R[3 * c + 1] * dv[1][i] + R[3 * c + 2] * dv[2][i];
        }
    for (j = 0; j < 3; j++) {
        const double *Rj = R + 3 * j, *dRj = dR + 3 * j * k;
        double *o = dY + (TR_Y_R + 3 * j) * k;
        FOR_K
        {
            o[0 * k + i] =
                dRj[1 * k + i] * u[2] - dRj[2 * k + i] * u[1] + Rj[1] * du[2][i] - Rj[2] * du[1][i];
            o[1 * k + i] =
                dRj[2 * k + i] * u[0] - dRj[0 * k + i] * u[2] + Rj[2] * du[0][i] - Rj[0] * du[2][i];
            o[2 * k + i] =
                dRj[0 * k + i] * u[1] - dRj[1 * k + i] * u[0] + Rj[0] * du[1][i] - Rj[1] * du[0][i];
        }
    }
    return 0;
}

static __attribute__((noinline)) int rhs_tangent1(const tr_model *m, const tr_data *d, double s,
                                                  const double *y, const double *Y,
                                                  const double *dtau, double *dy, double *dY)
{
    return rhs_tangent_body(m, d, s, y, Y, dtau, dy, dY, 1);
}

static __attribute__((noinline)) int rhs_tangent9(const tr_model *m, const tr_data *d, double s,
                                                  const double *y, const double *Y,
                                                  const double *dtau, double *dy, double *dY)
{
    return rhs_tangent_body(m, d, s, y, Y, dtau, dy, dY, 9);
}

static __attribute__((noinline)) int rhs_plain(const tr_model *m, const tr_data *d, double s,
                                               const double *y, double *dy)
{
    return rhs_spatial_body(m, d, s, y, dy, 0, 0);
}

/* ------------------------------------------------------------ scene input */
typedef struct {
    int nt, nl, nodes, K;
    double rod[6], tendons[NTMAX * 8], values[NTMAX], loads[16 * 7], dist[3];
} scene_in;

static int read_doubles(FILE *in, double *v, int n)
{
    int i;
    for (i = 0; i < n; i++)
        if (fscanf(in, "%lf", v + i) != 1) return -1;
    return 0;
}

static int read_scene(FILE *in, scene_in *s)
{
    if (fscanf(in, "%d %d %d %d", &s->nt, &s->nl, &s->nodes, &s->K) != 4 || s->nt < 0 ||
        s->nt > NTMAX || s->nl < 0 || s->nl > 16 || s->nodes < 1 || s->K < 1)
        return -1;
    if (read_doubles(in, s->rod, 6) || read_doubles(in, s->tendons, 8 * s->nt)) return -1;
    if (read_doubles(in, s->values, s->nt) || read_doubles(in, s->loads, 7 * s->nl) ||
        read_doubles(in, s->dist, 3))
        return -1;
    return 0;
}

/* ------------------------------------------------------------ timing */
static double cpu_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

static double wall_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

static int cmp(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *t, int n)
{
    qsort(t, (size_t)n, sizeof *t, cmp);
    return t[n / 2];
}

static int zero_rhs(double t, const double y[], double f[], void *p)
{
    (void)t;
    (void)p;
    (void)y;
    (void)f;
    return GSL_SUCCESS;
}

/* ------------------------------------------------------------ main */
#define PASSES 20
#define BMAX   2001

static double urand(unsigned long *st)
{
    *st = *st * 6364136223846793005UL + 1442695040888963407UL;
    return ((double)(*st >> 11) / 9007199254740992.0) * 2.0 - 1.0;
}

int main(int argc, char **argv)
{
    static scene_in sc;
    static double Y[YMAX * KMAX], dT[NTMAX * KMAX], dY[YMAX * KMAX], dyv[YMAX];
    static double t_rhs[BMAX], t_t1[BMAX], t_t9[BMAX], w_rhs[BMAX], w_t1[BMAX], w_t9[BMAX];
    static double st_n[BMAX], st_nk[BMAX];
    const int blocks = argc > 1 ? atoi(argv[1]) : 201;
    const double seed = argc > 2 ? atof(argv[2]) : 1e-3;
    char msg[TR_MSGLEN];
    tr_options o = tr_default_options();
    tr_model *m;
    tr_data *d;
    double *f, scale[YMAX], tscale[NTMAX], sink = 0.0;
    int i, j, c, b, p, n, ns, st, nb;
    unsigned long rs = 12345;

    gsl_set_error_handler_off();
    if (blocks < 3 || blocks > BMAX || read_scene(stdin, &sc) < 0) {
        fprintf(stderr, "sensitivity_spike: bad blocks or scene (see the header)\n");
        return 2;
    }
    for (j = 0; j < sc.nt; j++) sc.tendons[8 * j + 6] = sc.values[j];
    if (tr_model_alloc(&m, sc.rod, sc.tendons, sc.nt, sc.loads, sc.nl, sc.dist, &o, msg,
                       sizeof msg)) {
        fprintf(stderr, "model: %s\n", msg);
        return 1;
    }
    d = tr_data_alloc(m, &o, sc.nodes, NULL, msg, sizeof msg);
    if (!d) return 1;
    st = tr_solve(m, d, NULL, NULL);
    if (!TR_SUCCEEDED(st)) {
        fprintf(stderr, "solve: %s\n", tr_data_message(d));
        return 1;
    }
    n = m->n_states;
    nb = m->n_base;
    f = malloc((size_t)m->n_unknowns * sizeof *f);
    cap.ny = n;
    cap.on = 1;
    st = tr_residual(m, d, d->x, f);
    cap.on = 0;
    ns = cap.n;
    printf("scene: nt=%d ndisp=%d n_states=%d n_unknowns=%d nseg=%d kirchhoff=%d general=%d "
           "has_dist=%d; residual status %d, %d states captured\n",
           m->nt, m->ndisp, n, m->n_unknowns, m->nseg, m->kirchhoff, m->general, m->has_dist, st,
           ns);
    printf("tensions [N]:");
    for (j = 0; j < m->nt; j++) printf(" %.6g", d->tau[j]);
    printf("\n");
    if (ns < 1 || n > YMAX) return 1;

    /* seeds scaled per block: p by L, R by 1, n and m by the largest magnitude seen */
    {
        double nmax = 0.0, mmax = 0.0, tmax = 0.0;
        for (p = 0; p < ns; p++)
            for (c = 0; c < 3; c++) {
                nmax = fmax(nmax, fabs(cap.y[p][TR_Y_N + c]));
                mmax = fmax(mmax, fabs(cap.y[p][TR_Y_M + c]));
            }
        for (j = 0; j < m->nt; j++) tmax = fmax(tmax, fabs(d->tau[j]));
        nmax = fmax(nmax, tmax);
        mmax = fmax(mmax, 1e-3 * nmax);
        for (c = 0; c < n; c++)
            scale[c] = c < TR_Y_R   ? m->L
                       : c < TR_Y_N ? 1.0
                       : c < TR_Y_M ? nmax
                       : c < nb     ? mmax
                                    : m->L;
        for (j = 0; j < m->nt; j++) tscale[j] = fmax(tmax, 1e-3);
    }
    for (c = 0; c < n; c++)
        for (i = 0; i < KMAX; i++) Y[c * KMAX + i] = c < nb ? seed * scale[c] * urand(&rs) : 0.0;
    for (j = 0; j < m->nt; j++)
        for (i = 0; i < KMAX; i++) /* a slack tendon stays slack: no seed on its tension */
            dT[j * KMAX + i] = d->tau[j] > 0.0 ? seed * tscale[j] * urand(&rs) : 0.0;

    /* 2. the tangent against central differences, Richardson-extrapolated */
    {
        static double yp[YMAX], ym[YMAX], fp[YMAX], fm[YMAX], d1[YMAX], d2[YMAX];
        double tau0[NTMAX], worst[5] = {0, 0, 0, 0, 0}, pdiff = 0.0;
        const char *names[5] = {"p'", "R'", "n'", "m'", "len'"};
        const int lo[6] = {TR_Y_P, TR_Y_R, TR_Y_N, TR_Y_M, TR_Y_LEN, n};
        memcpy(tau0, d->tau, (size_t)m->nt * sizeof(double));
        for (p = 0; p < ns; p++) {
            d->seg = cap.seg[p];
            if (rhs_tangent9(m, d, cap.s[p], cap.y[p], Y, dT, dyv, dY) != 0) {
                fprintf(stderr, "tangent: outside the prototype's formulation\n");
                return 1;
            }
            rhs_plain(m, d, cap.s[p], cap.y[p], fp);
            for (c = 0; c < n; c++) pdiff = fmax(pdiff, fabs(fp[c] - dyv[c]));
            for (i = 0; i < KMAX; i++) {
                double h = 1.0;
                int r;
                for (r = 0; r < 2; r++, h *= 0.5) {
                    double *dd = r ? d2 : d1;
                    for (c = 0; c < n; c++) {
                        yp[c] = cap.y[p][c] + h * Y[c * KMAX + i];
                        ym[c] = cap.y[p][c] - h * Y[c * KMAX + i];
                    }
                    for (j = 0; j < m->nt; j++) d->tau[j] = tau0[j] + h * dT[j * KMAX + i];
                    rhs_plain(m, d, cap.s[p], yp, fp);
                    for (j = 0; j < m->nt; j++) d->tau[j] = tau0[j] - h * dT[j * KMAX + i];
                    rhs_plain(m, d, cap.s[p], ym, fm);
                    for (c = 0; c < n; c++) dd[c] = (fp[c] - fm[c]) / (2.0 * h);
                }
                memcpy(d->tau, tau0, (size_t)m->nt * sizeof(double));
                for (b = 0; b < 5; b++) {
                    double emax = 0.0, fmx = 0.0;
                    for (c = lo[b]; c < lo[b + 1]; c++) {
                        const double fd = (4.0 * d2[c] - d1[c]) / 3.0;
                        emax = fmax(emax, fabs(dY[c * KMAX + i] - fd));
                        fmx = fmax(fmx, fabs(fd));
                    }
                    if (fmx > 0.0) worst[b] = fmax(worst[b], emax / fmx);
                }
            }
        }
        printf("check (%d states x %d directions, seeds %g of the scales, FD steps 1 and 1/2 "
               "of the seed, Richardson): primal |dy - kernel| max %.3g\n",
               ns, KMAX, seed, pdiff);
        printf("  max relative error per block:");
        for (b = 0; b < 5; b++) printf(" %s %.2e", names[b], worst[b]);
        printf("\n");
    }

    /* 3. timing, interleaved: kernel; kernel + tangent k = 1; k = 9 */
    for (b = 0; b < blocks; b++) {
        double c0, w0;
        c0 = cpu_now(), w0 = wall_now();
        for (j = 0; j < PASSES; j++)
            for (p = 0; p < ns; p++) {
                d->seg = cap.seg[p];
                rhs_plain(m, d, cap.s[p], cap.y[p], dyv);
                sink += dyv[TR_Y_N];
            }
        t_rhs[b] = cpu_now() - c0, w_rhs[b] = wall_now() - w0;
        c0 = cpu_now(), w0 = wall_now();
        for (j = 0; j < PASSES; j++)
            for (p = 0; p < ns; p++) {
                d->seg = cap.seg[p];
                rhs_tangent1(m, d, cap.s[p], cap.y[p], Y, dT, dyv, dY);
                sink += dyv[TR_Y_N] + dY[TR_Y_N];
            }
        t_t1[b] = cpu_now() - c0, w_t1[b] = wall_now() - w0;
        c0 = cpu_now(), w0 = wall_now();
        for (j = 0; j < PASSES; j++)
            for (p = 0; p < ns; p++) {
                d->seg = cap.seg[p];
                rhs_tangent9(m, d, cap.s[p], cap.y[p], Y, dT, dyv, dY);
                sink += dyv[TR_Y_N] + dY[TR_Y_N * KMAX];
            }
        t_t9[b] = cpu_now() - c0, w_t9[b] = wall_now() - w0;
    }
    {
        const double per = 1e9 / (PASSES * ns);
        const double tr = median(t_rhs, blocks) * per, t1 = median(t_t1, blocks) * per;
        const double t9 = median(t_t9, blocks) * per, wr = median(w_rhs, blocks) * per;
        const double w1 = median(w_t1, blocks) * per, w9 = median(w_t9, blocks) * per;
        printf("timing (%d blocks of %d passes over the %d states; ns per evaluation, median)\n",
               blocks, PASSES, ns);
        printf("  cpu : rhs %.1f  rhs+tangent k=1 %.1f  k=9 %.1f  ->  c(k=1) %.3f  c(k=9) %.3f\n",
               tr, t1, t9, (t1 - tr) / tr, (t9 - tr) / (9.0 * tr));
        printf("  wall: rhs %.1f  rhs+tangent k=1 %.1f  k=9 %.1f  ->  c(k=1) %.3f  c(k=9) %.3f\n",
               wr, w1, w9, (w1 - wr) / wr, (w9 - wr) / (9.0 * wr));
        /* the stepper's own work per step on n and n (1 + 9) states, trivial rhs */
        {
            gsl_odeiv2_system s1 = {zero_rhs, NULL, (size_t)n, NULL};
            gsl_odeiv2_system s9 = {zero_rhs, NULL, (size_t)(n * (1 + KMAX)), NULL};
            gsl_odeiv2_step *g1 = gsl_odeiv2_step_alloc(gsl_odeiv2_step_rk8pd, (size_t)n);
            gsl_odeiv2_step *g9 =
                gsl_odeiv2_step_alloc(gsl_odeiv2_step_rk8pd, (size_t)(n * (1 + KMAX)));
            static double ya[YMAX * (1 + KMAX)], ye[YMAX * (1 + KMAX)];
            const int steps = 200;
            for (c = 0; c < n * (1 + KMAX); c++) ya[c] = 0.5;
            for (b = 0; b < blocks; b++) {
                double c0 = cpu_now();
                for (j = 0; j < steps; j++)
                    gsl_odeiv2_step_apply(g1, 0, 1e-3, ya, ye, NULL, NULL, &s1);
                st_n[b] = cpu_now() - c0;
                c0 = cpu_now();
                for (j = 0; j < steps; j++)
                    gsl_odeiv2_step_apply(g9, 0, 1e-3, ya, ye, NULL, NULL, &s9);
                st_nk[b] = cpu_now() - c0;
            }
            {
                const double s1t = median(st_n, blocks) * 1e9 / steps;
                const double s9t = median(st_nk, blocks) * 1e9 / steps;
                printf("  rk8pd step_apply, trivial rhs (cpu ns per step; 13 evaluations a step): "
                       "n=%d %.0f (%.2f rhs-equivalents per evaluation), n=%d %.0f (%.2f); "
                       "added per evaluation by k=9: %.2f rhs-equivalents\n",
                       n, s1t, s1t / 13.0 / tr, n * (1 + KMAX), s9t, s9t / 13.0 / tr,
                       (s9t - s1t) / 13.0 / tr);
            }
            gsl_odeiv2_step_free(g1);
            gsl_odeiv2_step_free(g9);
        }
    }
    /* (a third argument: only that many default cold solves, for a profiler) */
    if (argc > 3) {
        const int nsol = atoi(argv[3]);
        for (b = 0; b < nsol; b++) {
            tr_model *mc;
            tr_data *dc;
            if (tr_model_alloc(&mc, sc.rod, sc.tendons, sc.nt, sc.loads, sc.nl, sc.dist, &o, msg,
                               sizeof msg))
                return 1;
            dc = tr_data_alloc(mc, &o, sc.nodes, NULL, msg, sizeof msg);
            if (!dc) return 1;
            tr_data_set_lazy(dc, 1);
            if (b == 0) printf("right-hand side calls per shooting pass of a cold solve:");
            cap.on = b == 0 ? 2 : 0;
            cap.mark = cap.calls;
            tr_solve(mc, dc, NULL, NULL);
            if (b == 0) printf(" %ld (and after)\n", cap.calls - cap.mark);
            cap.on = 0;
            tr_data_free(dc);
            tr_model_free(mc);
        }
        return 0;
    }
    /* 4. where the evaluations stand in a cold solve: CPU time of compile + tr_solve +
     * free (as bench/solve_harness.c's cold), right-hand side calls, nfev and njev, with
     * the default options and with accept_unstable (no verdict) */
    {
        int au;
        for (au = 0; au < 2; au++) {
            static double tc[BMAX];
            tr_options oc = tr_default_options();
            tr_result res;
            long calls = 0;
            const int reps = blocks < 101 ? blocks : 101;
            oc.accept_unstable = au;
            for (b = 0; b < reps; b++) {
                tr_model *mc;
                tr_data *dc;
                const double c0 = cpu_now();
                const long k0 = cap.calls;
                if (tr_model_alloc(&mc, sc.rod, sc.tendons, sc.nt, sc.loads, sc.nl, sc.dist, &oc,
                                   msg, sizeof msg))
                    return 1;
                dc = tr_data_alloc(mc, &oc, sc.nodes, NULL, msg, sizeof msg);
                if (!dc) return 1;
                tr_data_set_lazy(dc, 1);
                st = tr_solve(mc, dc, NULL, NULL);
                tr_data_result(dc, &res);
                tr_data_free(dc);
                tr_model_free(mc);
                tc[b] = cpu_now() - c0;
                calls = cap.calls - k0;
                if (!TR_SUCCEEDED(st)) return 1;
            }
            printf("cold solve%s: cpu %.1f us (median of %d), nfev %d, njev %d, nit %d, "
                   "rhs calls %ld\n",
                   au ? " accept_unstable" : " default", median(tc, reps) * 1e6, reps, res.nfev,
                   res.njev, res.nit, calls);
        }
    }
    fprintf(stderr, "(sink %g)\n", sink);
    free(f);
    tr_data_free(d);
    tr_model_free(m);
    return 0;
}
