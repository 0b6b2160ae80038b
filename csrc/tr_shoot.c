/*
 * tr_shoot.c -- shooting: residual, init / iterate / test, the one-call
 * driver (continuation, step verification, conditioning), the recording pass
 * and the compliance by the implicit function theorem.
 *
 * Unknowns (scaled): the base reaction of backbone plus tendons,
 *   (n(0) + sum tau_i t0_i) / (EI/L^2),  (m(0) + sum tau_i r_i(0) x t0_i) / (EI/L)
 * (t0_i: tendon tangent of the straight robot; planar: x, z force and y moment),
 * which global balance fixes (nearly) independently of the tensions, so the
 * tension unknowns do not fight the backbone force; then one gamma per
 * displacement-controlled tendon:
 *   linear  (semismooth): tau = tau_s max(gamma, 0), slack = l_s max(-gamma, 0)
 *   squared (paper):      tau = tau_s gamma^2 (gamma >= 0), slack = l_s gamma^2 (gamma < 0)
 * (tau_s = EI/(r L), l_s = r, r the largest offset of a displacement-controlled
 * tendon: a unit of gamma then changes the path length by ~r on either side of
 * the switch, so the Jacobian is balanced).
 * Residuals (scaled): tip force / (EI/L^2) and moment / (EI/L), body frame,
 * then the length constraints E_i / l_s with
 *   E_i = s_i(t_i) + q_i + slack_i - (1 + tau_i/EA_i) rest_i
 * (the path length is integrated as its excess over the reference length, which
 * keeps the digits that stiff tendons need).
 */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>

#include "tendonrod.h"
#include "tr_internal.h"
#include "tru_math.h"

/* Forward-difference step for the Jacobian, scaled units: ~sqrt(machine eps). */
#define TR_FD_H 1.5e-8
/* Central-difference step for the compliance (scaled units): balances the
 * h^2 truncation (~1e-11) against round-off (~1e-16/h). */
#define TR_CD_H 3e-6
/* Largest Newton step (scaled max-norm): 10 ~ a curl of 10 rad per length. */
#define TR_MAX_STEP 10.0
/* Armijo constant of the backtracking line search. */
#define TR_ARMIJO 1e-4
/* Smallest line-search step before giving up. */
#define TR_ALPHA_MIN 1e-6
/* A stalled scaled residual below this is probably round-off, not a bad model. */
#define TR_ROUNDOFF_HINT 1e-8
/* A Broyden step reducing the residual by less than this factor triggers a
 * fresh finite-difference Jacobian. */
#define TR_BROYDEN_RATIO 0.5
/* Condition number (1-norm, scaled) above which the Jacobian counts as singular. */
#define TR_COND_SINGULAR 1e12
/* Automatic step count: initial totals and the cap of the doubling. */
#define TR_AUTO_RK8 2
#define TR_AUTO_RK4 16
/* ... and at least this many rk8 steps per unit of L sqrt(|F|/EI) (boundary layers) */
#define TR_AUTO_PER_LAMBDA 2.0
#define TR_STEP_CAP        8192
/* Step refinement aims the Richardson-predicted truncation at this fraction of tol. */
#define TR_REFINE_SAFETY 0.5
/* Cap of the initial automatic step count (huge loads: keep max_nfev a time bound). */
#define TR_AUTO_MAX 256
/* Recording pass: RK4 steps of at most this fraction of the rk8 shooting step. */
#define TR_RECORD_RK4_FRACTION  8.0
#define TR_RECORD_RK4_MIN_STEPS 100.0
/* ... and is redone with rk8 if its tip differs from the shooting tip by more than
 * this (scaled states): a guard against gross RK4 errors (unresolved boundary
 * layers); otherwise the tip node takes the shooting tip. */
#define TR_RECORD_GROSS 1e-6
/* Continuation: first step and smallest step in lambda. */
#define TR_CONT_DLAM0    0.25
#define TR_CONT_DLAM_MIN 1e-4
/* Polish: at most this many extra Newton steps, taken while the step exceeds this
 * factor times tol (relative to max(1, |x|)). */
#define TR_POLISH_STEPS       3
#define TR_POLISH_XTOL_FACTOR 1e3
#define TR_POLISH_RES_FACTOR  1e-2
/* Iterations per continuation step: Newton from a near point converges in a few. */
#define TR_CONT_ITER 15
/* A direct Newton run whose residual fell by less than 1/TR_STALL_RATIO over the
 * last TR_STALL_ITERS iterations is abandoned as stagnating (creeping damped steps:
 * measured on Fig. 11c with stiff tendons under twist, the residual stays at ~2e-3
 * for 50+ iterations; a creep that ends in the Newton basin, as at r^2kL/3EI = 500,
 * halves the residual in ~8 iterations and is kept) ... */
#define TR_STALL_ITERS 8
/* A failed solve with displacement-controlled tendons stiffer than this (r^2 EA/EI)
 * says so in its message (Fig. 12 twist fails from ~1e10, converges at 1e8). */
#define TR_STIFF_HINT  1e6
#define TR_STALL_RATIO 0.8
/* ... and a continuation stage over TR_CONT_STALL_ITERS iterations (then the step is
 * halved).  A stricter test (2x over 4) made Fig. 12 at r^2kL/EI = 1e8 stall at the
 * first load stage: its stages creep for ~5 iterations and then converge. */
#define TR_CONT_STALL_ITERS 6
#define TR_CONT_STALL_RATIO 0.8
/* Cold starts with loads above this scaled magnitude (sum of |F| L^2/EI, |M| L/EI,
 * |f| L^3/EI) go by continuation at once, in load steps of at most TR_RAMP_LOAD. */
#define TR_DIRECT_LOAD_MAX 6.0
#define TR_RAMP_LOAD       3.0
/* A continuation stage may move the tip by at most this fraction of L. */
#define TR_CONT_TIP_JUMP 0.2
/* Newton iterations of the implicit jump at a breakpoint (converges in 2-4). */
#define TR_JUMP_ITER 20

void tr_set_message(tr_data *d, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(d->message, TR_MSGLEN, fmt, ap);
    va_end(ap);
}

static double maxnorm(const double *v, int n)
{
    double r = 0.0;
    int i;
    for (i = 0; i < n; i++) {
        const double a = fabs(v[i]);
        if (!(a <= r)) r = a; /* propagates NaN */
    }
    return r;
}

static double sumsq(const double *v, int n)
{
    double r = 0.0;
    int i;
    for (i = 0; i < n; i++) r += v[i] * v[i];
    return r;
}

static int n_force(const tr_model *m)
{
    return m->planar ? 3 : 6;
}

static void set_tensions(const tr_model *m, tr_data *d, const double *x)
{
    const int off = n_force(m);
    int i;
    for (i = 0; i < m->nt; i++) {
        const tr_tendon *t = &m->tendon[i];
        if (t->control == TR_DISPLACEMENT) {
            const double g = x[off + t->gamma_index];
            if (d->opt.slack_model == TR_SLACK_SQUARED) {
                d->tau[i] = g > 0.0 ? m->tau_s * g * g : 0.0;
                d->beta[i] = g < 0.0 ? m->len_s * g * g : 0.0;
            } else {
                d->tau[i] = g > 0.0 ? m->tau_s * g : 0.0;
                d->beta[i] = g < 0.0 ? -m->len_s * g : 0.0;
            }
        } else {
            d->tau[i] = d->lam_act * t->value;
            d->beta[i] = 0.0;
        }
    }
}

/* Base state from the unknowns (tensions already set): the backbone carries the
 * base reaction minus the tendon pulls. */
static void init_state(const tr_model *m, const tr_data *d, const double *x, double *y, int dim)
{
    double tn[3] = {0.0, 0.0, 0.0}, tm[3] = {0.0, 0.0, 0.0};
    int i;
    for (i = 0; i < m->nt; i++) {
        const double tau = d->tau[i];
        int c;
        for (c = 0; c < 3; c++) {
            tn[c] += tau * m->tendon[i].t0[c];
            tm[c] += tau * m->tendon[i].rt0[c];
        }
    }
    memset(y, 0, (size_t)dim * sizeof(double));
    if (m->planar) {
        y[TR_YP_N1] = x[0] * m->F_s - tn[0];
        y[TR_YP_N3] = x[1] * m->F_s - tn[2];
        y[TR_YP_M] = x[2] * m->M_s - tm[1];
    } else {
        y[TR_Y_R + 0] = y[TR_Y_R + 4] = y[TR_Y_R + 8] = 1.0;
        for (i = 0; i < 3; i++) {
            y[TR_Y_N + i] = x[i] * m->F_s - tn[i];
            y[TR_Y_M + i] = x[3 + i] * m->M_s - tm[i];
        }
    }
}

/* Loads at breakpoint b (world): point loads scaled by lam_load, plus the probe. */
static void bp_load(const tr_model *m, const tr_data *d, int b, double F[3], double M[3])
{
    int c;
    for (c = 0; c < 3; c++) {
        F[c] = d->lam_load * m->bpF[3 * b + c];
        M[c] = d->lam_load * m->bpM[3 * b + c];
    }
    if (b == d->probe_bp)
        for (c = 0; c < 3; c++) {
            F[c] += d->probe[c];
            M[c] += d->probe[3 + c];
        }
}

/* Sum of the anchor pulls of the tendons anchored at breakpoint b, body frame:
 * force sum tau t^, moment sum tau r x t^ (state just proximal of b). */
static void anchor_sum(const tr_model *m, const tr_data *d, int b, const double *y, double fn[3],
                       double fm[3])
{
    const double s = m->bp[b];
    int i;
    fn[0] = fn[1] = fn[2] = fm[0] = fm[1] = fm[2] = 0.0;
    for (i = 0; i < m->nt; i++) {
        double th[3], r[3], rt[3];
        const double tau = d->tau[i];
        if (m->tendon[i].end_bp != b || !(tau > 0.0)) continue;
        tr_tendon_tangent(m, i, s, y, th, r);
        tru_cross3(rt, r, th);
        fn[0] += tau * th[0];
        fn[1] += tau * th[1];
        fn[2] += tau * th[2];
        fm[0] += tau * rt[0];
        fm[1] += tau * rt[1];
        fm[2] += tau * rt[2];
    }
}

/* Jump at interior breakpoint b.  The whole section (backbone plus tendons)
 * carries the external load: its force and moment jump by the point load,
 *   n_b+ + sum_cont tau t^+ = n_b- + sum_all tau t^- - R^T P    (moments alike),
 * where "all" are the tendons active before b (those anchored at b hand their
 * pull to the backbone) and "cont" those continuing past it.  Where the jump
 * changes the strains (a Cosserat rod under a point force, any rod under a point
 * moment or an anchor), the continuing tendons kink and push on the backbone;
 * t^+ depends on n_b+, m_b+, so this is a small Newton solve with the matrix of
 * the right-hand side. */
static void apply_jump(const tr_model *m, const tr_data *d, int b, double *y)
{
    const double s = m->bp[b];
    double F[3], M[3], Fb[3], Mb[3], nb[3], mb[3], fn[3], fm[3], Cn[3], Cm[3];
    int c, it;
    bp_load(m, d, b, F, M);
    if (m->planar) {
        const double ct = cos(y[TR_YP_TH]), st = sin(y[TR_YP_TH]);
        Fb[0] = ct * F[0] - st * F[2];
        Fb[1] = 0.0;
        Fb[2] = st * F[0] + ct * F[2];
        Mb[0] = 0.0;
        Mb[1] = M[1];
        Mb[2] = 0.0;
        nb[0] = y[TR_YP_N1];
        nb[1] = 0.0;
        nb[2] = y[TR_YP_N3];
        mb[0] = 0.0;
        mb[1] = y[TR_YP_M];
        mb[2] = 0.0;
    } else {
        tru_mattvec3(Fb, y + TR_Y_R, F);
        tru_mattvec3(Mb, y + TR_Y_R, M);
        memcpy(nb, y + TR_Y_N, sizeof nb);
        memcpy(mb, y + TR_Y_M, sizeof mb);
    }
    tr_section_pulls(m, d, b - 1, s, nb, mb, fn, fm, NULL);
    for (c = 0; c < 3; c++) {
        Cn[c] = nb[c] + fn[c] - Fb[c];
        Cm[c] = mb[c] + fm[c] - Mb[c];
    }
    /* first guess: the continuing tendons keep their direction */
    tr_section_pulls(m, d, b, s, nb, mb, fn, fm, NULL);
    for (c = 0; c < 3; c++) {
        nb[c] = Cn[c] - fn[c];
        mb[c] = Cm[c] - fm[c];
    }
    for (it = 0; it < TR_JUMP_ITER; it++) {
        double J6[36], g[6], gmax = 0.0, scale = 0.0;
        tr_section_pulls(m, d, b, s, nb, mb, fn, fm, J6);
        for (c = 0; c < 3; c++) {
            g[c] = -(nb[c] + fn[c] - Cn[c]) / m->F_s;
            g[3 + c] = -(mb[c] + fm[c] - Cm[c]) / m->M_s;
            scale += fabs(Cn[c]) / m->F_s + fabs(Cm[c]) / m->M_s + fabs(fn[c]) / m->F_s;
        }
        for (c = 0; c < 6; c++)
            if (fabs(g[c]) > gmax) gmax = fabs(g[c]);
        if (gmax <= 1e-15 * (1.0 + scale)) break;
        /* (I + J6) dx = g in scaled units: columns of J6 times the unknowns' scales */
        {
            double Mx[36];
            int r_, c_;
            for (r_ = 0; r_ < 6; r_++)
                for (c_ = 0; c_ < 6; c_++) {
                    const double rs = r_ < 3 ? m->F_s : m->M_s, cs = c_ < 3 ? m->F_s : m->M_s;
                    Mx[6 * r_ + c_] = (r_ == c_) + J6[6 * r_ + c_] * cs / rs;
                }
            if (tru_solve_dense(6, Mx, g) != 0) break;
        }
        for (c = 0; c < 3; c++) {
            nb[c] += g[c] * m->F_s;
            mb[c] += g[3 + c] * m->M_s;
        }
    }
    if (m->planar) {
        y[TR_YP_N1] = nb[0];
        y[TR_YP_N3] = nb[2];
        y[TR_YP_M] = mb[1];
    } else {
        memcpy(y + TR_Y_N, nb, sizeof nb);
        memcpy(y + TR_Y_M, mb, sizeof mb);
    }
}

static void capture_probe(const tr_model *m, tr_data *d, const double *y)
{
    double n[3], mo[3];
    tr_state_world(m, y, d->probe_state, d->probe_state + 3, n, mo);
}

/* Tip residual (scaled) into f. */
static void tip_residual(const tr_model *m, tr_data *d, const double *y, double *f)
{
    double F[3], M[3], fn[3], fm[3];
    const int off = n_force(m);
    const int lenbase = m->planar ? TR_YP_LEN : TR_Y_LEN;
    int i;
    bp_load(m, d, m->nseg, F, M);
    anchor_sum(m, d, m->nseg, y, fn, fm);
    if (m->planar) {
        const double c = cos(y[TR_YP_TH]), s = sin(y[TR_YP_TH]);
        f[0] = (y[TR_YP_N1] + fn[0] - (c * F[0] - s * F[2])) / m->F_s;
        f[1] = (y[TR_YP_N3] + fn[2] - (s * F[0] + c * F[2])) / m->F_s;
        f[2] = (y[TR_YP_M] + fm[1] - M[1]) / m->M_s;
    } else {
        double Fb[3], Mb[3];
        int c;
        tru_mattvec3(Fb, y + TR_Y_R, F);
        tru_mattvec3(Mb, y + TR_Y_R, M);
        for (c = 0; c < 3; c++) {
            f[c] = (y[TR_Y_N + c] + fn[c] - Fb[c]) / m->F_s;
            f[3 + c] = (y[TR_Y_M + c] + fm[c] - Mb[c]) / m->M_s;
        }
    }
    for (i = 0; i < m->nt; i++) {
        const tr_tendon *t = &m->tendon[i];
        double E;
        if (t->control != TR_DISPLACEMENT) continue;
        /* s_i - (1 + tau/EA) rest with s_i = sref + excess, rest = sref + rest_dev */
        E = y[lenbase + (d->rec ? i : t->len_index)] + d->lam_act * t->value + d->beta[i] -
            t->rest_dev - (isfinite(t->EA) ? d->tau[i] / t->EA : 0.0) * t->rest;
        f[off + t->gamma_index] = E / m->len_s;
    }
}

/* ------------------------------------------------------ multiple shooting */
/* Magnitude of all external loads, scaled by EI/L^2 (forces) and EI/L (moments). */
static double tr_load_scale(const tr_model *m)
{
    double F = m->L * tru_norm3(m->dist) / m->F_s;
    int b;
    for (b = 1; b <= m->nseg; b++)
        F += tru_norm3(m->bpF + 3 * b) / m->F_s + tru_norm3(m->bpM + 3 * b) / m->M_s;
    return F;
}

/* Offset of shooting node j (1..M-1) in the unknowns and in the residuals. */
static int node_off(const tr_model *m, int j)
{
    return n_force(m) + m->ndisp + (j - 1) * m->n_states;
}

static double node_scale(const tr_model *m, int c)
{
    return c < m->n_base ? m->xstate_scale[c] : m->len_s;
}

/* At shooting node j: continuity residual (integrated minus unknown, scaled) into f
 * (if f != NULL), then restart from the unknown state. */
static void node_restart(const tr_model *m, const double *x, int j, double *y, double *f)
{
    const int o = node_off(m, j), ns = m->n_states;
    int c;
    for (c = 0; c < ns; c++) {
        const double sc = node_scale(m, c);
        if (f) f[o + c] = y[c] / sc - x[o + c];
        y[c] = x[o + c] * sc;
    }
}

/* Shape pass of a cold start: integrate the robot under its (guessed) tensions with
 * the loads off, record the pose at every breakpoint, then
 *  - set the base-reaction moment unknowns to the moment of the loads about the
 *    base in that actuated shape (the straight-robot estimate misses e.g. a vertical
 *    load on a bent robot), and
 *  - with multiple shooting, set each node to the unloaded state plus the section
 *    load (force and moment of the distal loads about the node, in that shape):
 *    under tensile loads this keeps every segment near its linear regime.
 * Where the pass does not stay finite, the straight robot stands in. */
static void shape_guess(const tr_model *m, tr_data *d, double *x)
{
    const int ns = m->n_states, nf = n_force(m);
    double *y = d->y, *pose = d->bp_pose;
    const double lam_load = d->lam_load;
    int b, c, ok = 1;
    /* unloaded base state: base reaction zero */
    for (c = 0; c < nf; c++) d->xt[c] = 0.0;
    for (c = nf; c < d->k; c++) d->xt[c] = x[c];
    d->rec = 0;
    d->lam_load = 0.0;
    set_tensions(m, d, d->xt);
    init_state(m, d, d->xt, y, ns);
    for (b = 0; b <= m->nseg; b++) {
        if (b > 0) {
            d->seg = b - 1;
            if (ok && tr_integrate(m, d, m->bp[b - 1], m->bp[b], tr_segment_steps(m, d, b - 1),
                                   y) != TR_OK)
                ok = 0;
            if (ok && b < m->nseg) apply_jump(m, d, b, y);
        }
        if (ok) {
            double n_[3], mo[3];
            tr_state_world(m, y, pose + 12 * b, pose + 12 * b + 3, n_, mo);
            for (c = 0; c < 12 && ok; c++)
                if (!isfinite(pose[12 * b + c])) ok = 0;
        }
        if (!ok) {
            /* straight robot */
            memset(pose + 12 * b, 0, 12 * sizeof(double));
            pose[12 * b + 2] = m->bp[b];
            pose[12 * b + 3] = pose[12 * b + 7] = pose[12 * b + 11] = 1.0;
        }
        if (b > 0 && b < m->nseg && m->bp_node[b] > 0) {
            /* unloaded state, stored for the node (loads added below) */
            const int o = node_off(m, m->bp_node[b]);
            for (c = 0; c < ns; c++)
                x[o + c] = ok ? y[c] : (c == (m->planar ? TR_YP_Z : TR_Y_P + 2) ? m->bp[b] : 0.0);
            if (!ok && !m->planar) x[o + TR_Y_R] = x[o + TR_Y_R + 4] = x[o + TR_Y_R + 8] = 1.0;
        }
    }
    d->lam_load = lam_load;
    /* loads about each section in that shape */
    for (b = 0; b < m->nseg; b++) {
        double F[3] = {0, 0, 0}, M[3] = {0, 0, 0}, arm[3], tmp[3];
        const double *pb = pose + 12 * b;
        int bb;
        if (b > 0 && (b >= m->nseg || m->bp_node[b] == 0)) continue;
        for (bb = b + 1; bb <= m->nseg; bb++) {
            const double *Fb = m->bpF + 3 * bb;
            for (c = 0; c < 3; c++) arm[c] = pose[12 * bb + c] - pb[c];
            tru_cross3(tmp, arm, Fb);
            for (c = 0; c < 3; c++) {
                F[c] += lam_load * Fb[c];
                M[c] += lam_load * (tmp[c] + m->bpM[3 * bb + c]);
            }
        }
        if (m->has_dist) {
            /* int_s^L (p - p_b) x f: trapezoid over the breakpoints */
            for (bb = b + 1; bb <= m->nseg; bb++) {
                const double h = m->bp[bb] - m->bp[bb - 1];
                double mid[3];
                for (c = 0; c < 3; c++)
                    mid[c] = 0.5 * (pose[12 * bb + c] + pose[12 * (bb - 1) + c]) - pb[c];
                tru_cross3(tmp, mid, m->dist);
                for (c = 0; c < 3; c++) M[c] += lam_load * h * tmp[c];
            }
            for (c = 0; c < 3; c++) F[c] += lam_load * (m->L - m->bp[b]) * m->dist[c];
        }
        if (b == 0) {
            /* base reaction (world = base frame) */
            if (m->planar) {
                x[0] = F[0] / m->F_s;
                x[1] = F[2] / m->F_s;
                x[2] = M[1] / m->M_s;
            } else {
                for (c = 0; c < 3; c++) {
                    x[c] = F[c] / m->F_s;
                    x[3 + c] = M[c] / m->M_s;
                }
            }
        } else {
            const int o = node_off(m, m->bp_node[b]);
            const double *R = pb + 3;
            double Fb[3], Mb[3];
            tru_mattvec3(Fb, R, F);
            tru_mattvec3(Mb, R, M);
            if (m->planar) {
                x[o + TR_YP_N1] += Fb[0];
                x[o + TR_YP_N3] += Fb[2];
                x[o + TR_YP_M] += Mb[1];
            } else {
                for (c = 0; c < 3; c++) {
                    x[o + TR_Y_N + c] += Fb[c];
                    x[o + TR_Y_M + c] += Mb[c];
                }
            }
            for (c = 0; c < ns; c++) x[o + c] /= node_scale(m, c);
        }
    }
}

static void cold_guess(const tr_model *m, tr_data *d, double *x);

/* Cold start: the straight-robot base moment or the shape pass's, whichever has
 * the smaller residual (a load on a bent robot wants the shape; a strong tensile
 * load that straightens the robot wants the straight one); nodes from the shape. */
static void cold_start(const tr_model *m, tr_data *d)
{
    const int nf = n_force(m), k = d->k;
    double ra = INFINITY, rb = INFINITY;
    int c;
    cold_guess(m, d, d->x);
    for (c = 0; c < nf; c++) d->fs[c] = d->x[c];
    shape_guess(m, d, d->x);
    if (tr_residual(m, d, d->x, d->ft) == TR_OK) rb = sumsq(d->ft, k);
    for (c = 0; c < nf; c++) {
        d->xp[c] = d->x[c];
        d->x[c] = d->fs[c];
    }
    if (tr_residual(m, d, d->x, d->ft) == TR_OK) ra = sumsq(d->ft, k);
    if (!(ra <= rb))
        for (c = 0; c < nf; c++) d->x[c] = d->xp[c];
}

/* Node unknowns from a given base state (warm start): integrate from it; if the
 * trajectory runs away, fall back to the shape pass. */
static void init_nodes(const tr_model *m, tr_data *d, double *x)
{
    const int ns = m->n_states;
    double *y = d->y, tsum = 0.0;
    int k, j, ok = 1, c;
    if (m->nshoot <= 1) return;
    d->rec = 0;
    set_tensions(m, d, x);
    for (c = 0; c < m->nt; c++) tsum += d->tau[c] / m->F_s;
    init_state(m, d, x, y, ns);
    for (k = 0; k < m->nseg && ok; k++) {
        const int b = k + 1;
        d->seg = k;
        if (tr_integrate(m, d, m->bp[k], m->bp[b], tr_segment_steps(m, d, k), y) != TR_OK) ok = 0;
        for (c = 0; c < m->n_base && ok; c++) {
            /* run away: position beyond 2 L, force/moment beyond 1e3 of the loads' scale */
            const double lim =
                (c < (m->planar ? 2 : 3)) ? 2.0 : 1e3 * (1.0 + tr_load_scale(m) + tsum);
            if (!(fabs(y[c]) / node_scale(m, c) <= lim)) ok = 0;
        }
        if (ok && b < m->nseg) apply_jump(m, d, b, y);
        if (ok && b < m->nseg && (j = m->bp_node[b]) > 0)
            for (c = 0; c < ns; c++) x[node_off(m, j) + c] = y[c] / node_scale(m, c);
    }
    if (!ok) {
        /* keep the given base unknowns */
        for (c = 0; c < n_force(m); c++) d->ft[c] = x[c];
        shape_guess(m, d, x);
        for (c = 0; c < n_force(m); c++) x[c] = d->ft[c];
    }
}

int tr_residual(const tr_model *m, tr_data *d, const double *x, double *f)
{
    int k, status;
    double *y = d->y;
    d->rec = 0;
    d->nfev++;
    set_tensions(m, d, x);
    init_state(m, d, x, y, m->n_states);
    for (k = 0; k < m->nseg; k++) {
        d->seg = k;
        status = tr_integrate(m, d, m->bp[k], m->bp[k + 1], tr_segment_steps(m, d, k), y);
        if (status != TR_OK) return status;
        if (k + 1 == d->probe_bp) capture_probe(m, d, y);
        if (k + 1 < m->nseg) {
            apply_jump(m, d, k + 1, y);
            if (m->bp_node[k + 1] > 0) node_restart(m, x, m->bp_node[k + 1], y, f);
        }
    }
    tip_residual(m, d, y, f);
    return isfinite(maxnorm(f, d->k)) ? TR_OK : TR_ENONFINITE;
}

/* ---------------------------------------------------------------- Newton */
/* int_0^T r_i . r_j ds for linear routings (body frame, straight robot). */
static double rr_integral(const tr_tendon *ti, const tr_tendon *tj, double T)
{
    const double cdp = ti->cphi * tj->cphi + ti->sphi * tj->sphi;
    return cdp * (ti->a * tj->a * T * T * T / 3.0 + 0.5 * (ti->a * tj->b + tj->a * ti->b) * T * T +
                  ti->b * tj->b * T);
}

/* int_0^T (m1 r_i2 - m2 r_i1) ds, m = moment of the loads distal of s about the
 * centreline of the straight robot (world = body): the path-length change the
 * loads alone cause is this / EI.  Integrands are polynomials of degree <= 3 in s on
 * each piece: 2-point Gauss-Legendre is exact. */
static double load_path_integral(const tr_model *m, const tr_data *d, const tr_tendon *ti, double T)
{
    const double gx[2] = {0.5 - 0.5 / sqrt(3.0), 0.5 + 0.5 / sqrt(3.0)};
    double sum = 0.0;
    int b, g;
    for (b = 1; b <= m->nseg; b++) {
        const double z = m->bp[b], top = z < T ? z : T;
        const double *F = m->bpF + 3 * b, *M = m->bpM + 3 * b;
        if (F[0] == 0.0 && F[1] == 0.0 && M[0] == 0.0 && M[1] == 0.0) continue;
        for (g = 0; g < 2; g++) {
            const double s = gx[g] * top, rho = ti->a * s + ti->b;
            const double m1 = -(z - s) * F[1] + M[0], m2 = (z - s) * F[0] + M[1];
            sum += 0.5 * top * (m1 * rho * ti->sphi - m2 * rho * ti->cphi);
        }
    }
    if (m->has_dist) {
        for (g = 0; g < 2; g++) {
            const double s = gx[g] * T, rho = ti->a * s + ti->b, h = 0.5 * (m->L - s) * (m->L - s);
            const double m1 = -h * m->dist[1], m2 = h * m->dist[0];
            sum += 0.5 * T * (m1 * rho * ti->sphi - m2 * rho * ti->cphi);
        }
    }
    return d->lam_load * sum;
}

/* Cold guess: the base reaction from global balance of the straight robot (exact
 * for the force); the tensions from the small-deflection linear model about the
 * straight robot (MODEL.md "links to the closed forms"):
 *   sum_j C_ij tau_j = q_i + (load term)_i - sum_{j tension-controlled} C_ij tau_j,
 *   C_ij = int r_i.r_j / EI + delta_ij t_i/EA_i + min(t_i, t_j)/EA_backbone,
 * with an active set for slack tendons (negative tension -> slack, re-solve); the
 * tensions are offsets from the pretensions.  If that system is singular (an
 * indeterminate set) each tendon gets its own diagonal estimate. */
static void cold_guess(const tr_model *m, tr_data *d, double *x)
{
    const int off = n_force(m), nd = m->ndisp;
    double F[3] = {0, 0, 0}, M[3] = {0, 0, 0};
    double *C = d->lin, *rhs = d->lin + nd * nd, *sol = rhs + nd, *A = sol + nd;
    int *act = d->lin_act, *map = d->lin_act + nd;
    int i, j, b, c, round;
    memset(x, 0, (size_t)d->k * sizeof(double));
    for (b = 1; b <= m->nseg; b++) {
        const double s = m->bp[b];
        for (c = 0; c < 3; c++) {
            F[c] += m->bpF[3 * b + c];
            M[c] += m->bpM[3 * b + c];
        }
        /* s e3 x F = s (-Fy, Fx, 0) */
        M[0] += -s * m->bpF[3 * b + 1];
        M[1] += s * m->bpF[3 * b + 0];
    }
    for (c = 0; c < 3; c++) F[c] += m->L * m->dist[c];
    M[0] += -0.5 * m->L * m->L * m->dist[1];
    M[1] += 0.5 * m->L * m->L * m->dist[0];
    for (c = 0; c < 3; c++) {
        F[c] *= d->lam_load;
        M[c] *= d->lam_load;
    }
    if (m->planar) {
        x[0] = F[0] / m->F_s;
        x[1] = F[2] / m->F_s;
        x[2] = M[1] / m->M_s;
    } else {
        for (c = 0; c < 3; c++) {
            x[c] = F[c] / m->F_s;
            x[3 + c] = M[c] / m->M_s;
        }
    }
    if (nd == 0) return;
    /* the linear system over displacement-controlled tendons */
    for (i = 0; i < m->nt; i++) {
        const tr_tendon *ti = &m->tendon[i];
        int ii = ti->gamma_index;
        if (ti->control != TR_DISPLACEMENT) continue;
        rhs[ii] = d->lam_act * ti->value + load_path_integral(m, d, ti, ti->t) / m->EI;
        for (j = 0; j < m->nt; j++) {
            const tr_tendon *tj = &m->tendon[j];
            const double T = ti->t < tj->t ? ti->t : tj->t;
            double cij = rr_integral(ti, tj, T) / m->EI + (m->kirchhoff ? 0.0 : T / m->EA);
            if (i == j && isfinite(ti->EA)) cij += ti->t / ti->EA;
            if (tj->control == TR_DISPLACEMENT)
                C[ii * nd + tj->gamma_index] = cij;
            else
                rhs[ii] -= cij * d->lam_act * tj->value;
        }
        act[ii] = 1;
        d->lin[2 * nd * nd + 2 * nd + ii] = ti->pretension;
    }
    for (round = 0; round <= nd; round++) {
        int na = 0, neg = 0, ok;
        for (i = 0; i < nd; i++)
            if (act[i]) map[na++] = i;
        for (i = 0; i < na; i++) {
            for (j = 0; j < na; j++) A[i * na + j] = C[map[i] * nd + map[j]];
            sol[i] = rhs[map[i]];
        }
        ok = na == 0 || tru_solve_dense(na, A, sol) == 0;
        for (i = 0; ok && i < na; i++)
            if (!isfinite(sol[i]) || fabs(sol[i]) > 1e6 * m->tau_s) ok = 0;
        if (!ok) {
            /* singular: diagonal estimates */
            for (i = 0; i < nd; i++) {
                act[i] = C[i * nd + i] > 0.0 && rhs[i] > 0.0;
                sol[i] = act[i] ? rhs[i] / C[i * nd + i] : 0.0;
                map[i] = i;
            }
            na = nd;
            for (i = 0; i < nd; i++) A[i] = sol[i];
            for (i = 0; i < nd; i++) sol[i] = act[i] ? A[i] : 0.0;
            break;
        }
        /* scatter, drop the most negative tension */
        {
            double worst = 0.0;
            int wi = -1;
            for (i = 0; i < na; i++) {
                const double tau_i = d->lin[2 * nd * nd + 2 * nd + map[i]] + sol[i];
                if (tau_i < worst) {
                    worst = tau_i;
                    wi = map[i];
                }
            }
            if (wi >= 0) {
                act[wi] = 0;
                neg = 1;
            }
            for (i = 0; i < nd; i++) A[i] = 0.0;
            for (i = 0; i < na; i++) A[map[i]] = sol[i];
            for (i = 0; i < nd; i++) sol[i] = A[i];
        }
        if (!neg) break;
    }
    for (i = 0; i < m->nt; i++) {
        const tr_tendon *t = &m->tendon[i];
        const int ii = t->gamma_index;
        double tau, g;
        if (t->control != TR_DISPLACEMENT) continue;
        tau = t->pretension + (act[ii] ? sol[ii] : 0.0);
        if (tau > 0.0) {
            g = tau / m->tau_s;
            x[off + ii] = d->opt.slack_model == TR_SLACK_SQUARED ? sqrt(g) : g;
        } else {
            /* slack = what the taut tendons leave of its constraint */
            double sl = -rhs[ii];
            for (j = 0; j < nd; j++) sl += C[ii * nd + j] * (act[j] ? sol[j] : 0.0);
            if (sl < 0.0) sl = 0.0;
            g = sl / m->len_s;
            x[off + ii] = d->opt.slack_model == TR_SLACK_SQUARED ? -sqrt(g) : -g;
        }
    }
}

/* One forward-difference column j of the Jacobian at d->x (d->f). */
static int fd_column(const tr_model *m, tr_data *d, int j)
{
    const int k = d->k;
    int i, status;
    double h = TR_FD_H * (fabs(d->x[j]) > 1.0 ? fabs(d->x[j]) : 1.0);
    memcpy(d->xt, d->x, (size_t)k * sizeof(double));
    d->xt[j] += h;
    h = d->xt[j] - d->x[j];
    status = tr_residual(m, d, d->xt, d->ft);
    if (status != TR_OK) return status;
    for (i = 0; i < k; i++) d->J[i * k + j] = (d->ft[i] - d->f[i]) / h;
    return TR_OK;
}

static int fd_jacobian(const tr_model *m, tr_data *d)
{
    const int k = d->k;
    int i, j, status;
    if (d->nfev + k > d->opt.max_nfev) {
        tr_set_message(d,
                       "function-evaluation limit (max_nfev = %d) reached: a Jacobian needs %d "
                       "more evaluations; raise max_nfev",
                       d->opt.max_nfev, k);
        return TR_EMAXFEV;
    }
    for (j = 0; j < k; j++) {
        double h = TR_FD_H * (fabs(d->x[j]) > 1.0 ? fabs(d->x[j]) : 1.0);
        memcpy(d->xt, d->x, (size_t)k * sizeof(double));
        d->xt[j] += h;
        h = d->xt[j] - d->x[j];
        status = tr_residual(m, d, d->xt, d->ft);
        if (status != TR_OK) {
            /* try the other side */
            d->xt[j] = d->x[j] - h;
            status = tr_residual(m, d, d->xt, d->ft);
            if (status != TR_OK) return status;
            h = -h;
        }
        for (i = 0; i < k; i++) d->J[i * k + j] = (d->ft[i] - d->f[i]) / h;
    }
    d->njev++;
    d->have_J = 1;
    d->J_fresh = 1;
    d->J_refresh = 0;
    return TR_OK;
}

/* LU of d->J into d->LU.  Returns 0 or -1 if singular. */
static int factor(tr_data *d)
{
    const int k = d->k;
    int i, signum;
    double dmax = 0.0, dmin = INFINITY;
    for (i = 0; i < k * k; i++) d->LU->data[(i / k) * d->LU->tda + i % k] = d->J[i];
    if (gsl_linalg_LU_decomp(d->LU, d->perm, &signum) != GSL_SUCCESS) return -1;
    for (i = 0; i < k; i++) {
        const double a = fabs(gsl_matrix_get(d->LU, i, i));
        if (a > dmax) dmax = a;
        if (a < dmin) dmin = a;
    }
    if (!(dmin > 1e-300) || !(dmin > 1e-15 * dmax) || !isfinite(dmax)) return -1;
    return 0;
}

/* res = J^-1 rhs (after factor) */
static int lu_solve(tr_data *d, const double *rhs, double *res)
{
    gsl_vector_const_view b = gsl_vector_const_view_array(rhs, (size_t)d->k);
    gsl_vector_view xv = gsl_vector_view_array(res, (size_t)d->k);
    return gsl_linalg_LU_solve(d->LU, d->perm, &b.vector, &xv.vector) == GSL_SUCCESS ? 0 : -1;
}

int tr_solve_init(const tr_model *m, tr_data *d, const double *guess, const double *jac)
{
    const int k = d->k, off = n_force(m);
    int i, status;
    if (d->model != m) {
        tr_set_message(d, "workspace was allocated for a different model");
        return TR_EINVAL;
    }
    if (guess) {
        double tn[3] = {0, 0, 0}, tm[3] = {0, 0, 0};
        for (i = 0; i < m->nt; i++) {
            /* base reaction = backbone force + tendon pulls (see init_state) */
            const double tau = guess[6 + i] > 0.0 ? guess[6 + i] : 0.0;
            int c;
            for (c = 0; c < 3; c++) {
                tn[c] += tau * m->tendon[i].t0[c];
                tm[c] += tau * m->tendon[i].rt0[c];
            }
        }
        if (m->planar) {
            d->x[0] = (guess[0] + tn[0]) / m->F_s;
            d->x[1] = (guess[2] + tn[2]) / m->F_s;
            d->x[2] = (guess[4] + tm[1]) / m->M_s;
        } else {
            for (i = 0; i < 3; i++) {
                d->x[i] = (guess[i] + tn[i]) / m->F_s;
                d->x[3 + i] = (guess[3 + i] + tm[i]) / m->M_s;
            }
        }
        for (i = 0; i < m->nt; i++) {
            const tr_tendon *t = &m->tendon[i];
            const double tau = guess[6 + i], sl = guess[6 + m->nt + i];
            double g = 0.0;
            if (t->control != TR_DISPLACEMENT) continue;
            if (tau > 0.0)
                g = d->opt.slack_model == TR_SLACK_SQUARED ? sqrt(tau / m->tau_s) : tau / m->tau_s;
            else if (sl > 0.0)
                g = d->opt.slack_model == TR_SLACK_SQUARED ? -sqrt(sl / m->len_s) : -sl / m->len_s;
            d->x[off + t->gamma_index] = g;
        }
        for (i = 0; i < k; i++)
            if (!isfinite(d->x[i])) {
                tr_set_message(d, "guess contains a non-finite value");
                return TR_EINVAL;
            }
        init_nodes(m, d, d->x);
    } else {
        cold_start(m, d);
    }
    d->have_J = d->J_fresh = d->J_refresh = 0;
    if (jac) {
        memcpy(d->J, jac, (size_t)k * k * sizeof(double));
        d->have_J = 1;
        for (i = 0; i < k * k; i++)
            if (!isfinite(jac[i])) d->have_J = 0;
    }
    status = tr_residual(m, d, d->x, d->f);
    d->fnorm = maxnorm(d->f, k);
    if (status != TR_OK)
        tr_set_message(d, "the residual at the initial guess is not finite (the guess is far "
                          "from any equilibrium); try no guess, or a guess from a nearby scene");
    return status;
}

int tr_solve_test(const tr_model *m, const tr_data *d)
{
    (void)m;
    return d->fnorm <= d->opt.tol ? TR_OK : TR_CONTINUE;
}

int tr_solve_iterate(const tr_model *m, tr_data *d)
{
    const int k = d->k;
    int attempt, i, j;
    for (attempt = 0; attempt < 3; attempt++) {
        double phi0, alpha = 1.0, dmax;
        int status, accepted;
        if (!d->have_J || d->J_refresh ||
            (d->opt.jacobian_method == TR_JAC_NEWTON && !d->J_fresh)) {
            status = fd_jacobian(m, d);
            if (status != TR_OK) {
                if (status != TR_EMAXFEV)
                    tr_set_message(d, "the residual became non-finite while forming the Jacobian");
                return status;
            }
        }
        if (factor(d) != 0 || lu_solve(d, d->f, d->dx) != 0) {
            if (!d->J_fresh) {
                d->J_refresh = 1;
                continue;
            }
            tr_set_message(d,
                           "singular Jacobian at iteration %d (scaled residual %.3g): the "
                           "unknowns are not determined by the boundary conditions (statically "
                           "indeterminate tendons, or a tendon whose tension cannot act)",
                           d->nit, d->fnorm);
            return TR_ESINGULAR;
        }
        for (i = 0; i < k; i++) d->dx[i] = -d->dx[i];
        dmax = maxnorm(d->dx, k);
        if (dmax > TR_MAX_STEP)
            for (i = 0; i < k; i++) d->dx[i] *= TR_MAX_STEP / dmax;
        phi0 = sumsq(d->f, k);
        accepted = 0;
        for (;;) {
            double phi;
            if (d->nfev >= d->opt.max_nfev) {
                tr_set_message(d,
                               "function-evaluation limit (max_nfev = %d) reached at iteration %d "
                               "(scaled residual %.3g > tol %.3g); raise max_nfev",
                               d->opt.max_nfev, d->nit, d->fnorm, d->opt.tol);
                return TR_EMAXFEV;
            }
            for (i = 0; i < k; i++) d->xt[i] = d->x[i] + alpha * d->dx[i];
            status = tr_residual(m, d, d->xt, d->ft);
            phi = status == TR_OK ? sumsq(d->ft, k) : INFINITY;
            if (phi <= (1.0 - 2.0 * TR_ARMIJO * alpha) * phi0) {
                accepted = 1;
                break;
            }
            if (!d->J_fresh) {
                d->J_refresh = 1;
                break;
            }
            if (isfinite(phi)) {
                /* minimiser of the quadratic through phi0, slope -2 phi0, phi(alpha) */
                double an = phi0 * alpha * alpha / (phi - phi0 + 2.0 * phi0 * alpha);
                if (!(an >= 0.1 * alpha)) an = 0.1 * alpha;
                if (an > 0.5 * alpha) an = 0.5 * alpha;
                alpha = an;
            } else {
                alpha *= 0.25;
            }
            if (alpha < TR_ALPHA_MIN) {
                if (d->fnorm < TR_ROUNDOFF_HINT)
                    tr_set_message(d,
                                   "no progress at iteration %d: the scaled residual stalled at "
                                   "%.3g > tol %.3g, near the round-off level of this scene (large "
                                   "tensions or stiffness ratios); loosen tol",
                                   d->nit, d->fnorm, d->opt.tol);
                else
                    tr_set_message(d,
                                   "no progress at iteration %d: the line search found no "
                                   "decrease of the scaled residual (%.3g) along the Newton "
                                   "direction; the scene may have no equilibrium nearby (e.g. past "
                                   "a buckling or slack limit), or the guess is poor",
                                   d->nit, d->fnorm);
                return TR_ENOPROGRESS;
            }
        }
        if (!accepted) continue; /* stale Jacobian rejected: retry with a fresh one */
        /* accept */
        {
            const double ratio = sqrt(sumsq(d->ft, k) / (phi0 > 0.0 ? phi0 : 1.0));
            if (d->opt.jacobian_method == TR_JAC_FD) {
                /* good Broyden: J += (dF - J dx) dx^T / (dx^T dx) */
                double ss = 0.0;
                for (i = 0; i < k; i++) {
                    d->xs[i] = d->xt[i] - d->x[i];
                    ss += d->xs[i] * d->xs[i];
                }
                if (ss > 0.0) {
                    for (i = 0; i < k; i++) {
                        double r = d->ft[i] - d->f[i];
                        for (j = 0; j < k; j++) r -= d->J[i * k + j] * d->xs[j];
                        d->work[i] = r / ss;
                    }
                    for (i = 0; i < k; i++)
                        for (j = 0; j < k; j++) d->J[i * k + j] += d->work[i] * d->xs[j];
                }
            }
            /* semismooth switch: a tendon that changed between taut and slack has a
             * new Jacobian column (dtau/dgamma jumps); refresh just that column */
            {
                const int off = n_force(m), gend = off + m->ndisp;
                int nsw = 0;
                for (j = off; j < gend; j++)
                    d->lin_act[j - off] = (d->x[j] > 0.0) != (d->xt[j] > 0.0);
                memcpy(d->x, d->xt, (size_t)k * sizeof(double));
                memcpy(d->f, d->ft, (size_t)k * sizeof(double));
                if (d->opt.jacobian_method == TR_JAC_FD && !(ratio > TR_BROYDEN_RATIO))
                    for (j = off; j < gend; j++)
                        if (d->lin_act[j - off]) {
                            if (fd_column(m, d, j) != TR_OK) {
                                d->J_refresh = 1;
                                break;
                            }
                            nsw++;
                        }
                (void)nsw;
            }
            d->fnorm = maxnorm(d->f, k);
            d->J_fresh = 0;
            d->J_refresh = ratio > TR_BROYDEN_RATIO;
            d->nit++;
            return TR_CONTINUE;
        }
    }
    tr_set_message(d, "no progress at iteration %d even with a fresh Jacobian", d->nit);
    return TR_ENOPROGRESS;
}

/* ---- GSL hybridsj (Powell's dogleg) on the same residual and FD Jacobian */
static int hyb_f(const gsl_vector *x, void *params, gsl_vector *f)
{
    tr_data *d = (tr_data *)params;
    return tr_residual(d->model, d, x->data, f->data) == TR_OK ? GSL_SUCCESS : GSL_EBADFUNC;
}

static int hyb_jac(tr_data *d, const double *x, const double *f0, gsl_matrix *J)
{
    const tr_model *m = d->model;
    const int k = d->k;
    int i, j;
    if (d->nfev + k > d->opt.max_nfev) return GSL_EMAXITER;
    memcpy(d->xt, x, (size_t)k * sizeof(double));
    for (j = 0; j < k; j++) {
        double h = TR_FD_H * (fabs(x[j]) > 1.0 ? fabs(x[j]) : 1.0);
        d->xt[j] = x[j] + h;
        h = d->xt[j] - x[j];
        if (tr_residual(m, d, d->xt, d->ft) != TR_OK) return GSL_EBADFUNC;
        for (i = 0; i < k; i++) gsl_matrix_set(J, i, j, (d->ft[i] - f0[i]) / h);
        d->xt[j] = x[j];
    }
    d->njev++;
    return GSL_SUCCESS;
}

static int hyb_df(const gsl_vector *x, void *params, gsl_matrix *J)
{
    tr_data *d = (tr_data *)params;
    if (tr_residual(d->model, d, x->data, d->dx) != TR_OK) return GSL_EBADFUNC;
    return hyb_jac(d, x->data, d->dx, J);
}

static int hyb_fdf(const gsl_vector *x, void *params, gsl_vector *f, gsl_matrix *J)
{
    tr_data *d = (tr_data *)params;
    if (tr_residual(d->model, d, x->data, f->data) != TR_OK) return GSL_EBADFUNC;
    return hyb_jac(d, x->data, f->data, J);
}

static int hybrid_run(const tr_model *m, tr_data *d, int max_iter)
{
    const int k = d->k;
    gsl_multiroot_function_fdf F;
    gsl_vector_view xv = gsl_vector_view_array(d->x, (size_t)k);
    gsl_multiroot_fdfsolver *s = d->hyb;
    int it = 0, st, i, j, status = TR_CONTINUE;
    F.f = hyb_f;
    F.df = hyb_df;
    F.fdf = hyb_fdf;
    F.n = (size_t)k;
    F.params = d;
    st = gsl_multiroot_fdfsolver_set(s, &F, &xv.vector);
    if (st != GSL_SUCCESS) status = st == GSL_EMAXITER ? TR_EMAXFEV : TR_ENONFINITE;
    while (status == TR_CONTINUE) {
        double fn = maxnorm(s->f->data, k);
        if (fn <= d->opt.tol) {
            status = TR_OK;
            break;
        }
        if (it >= max_iter) {
            status = TR_EMAXITER;
            break;
        }
        if (d->nfev >= d->opt.max_nfev) {
            status = TR_EMAXFEV;
            break;
        }
        st = gsl_multiroot_fdfsolver_iterate(s);
        it++;
        if (st == GSL_EMAXITER)
            status = TR_EMAXFEV;
        else if (st == GSL_EBADFUNC)
            status = TR_ENONFINITE;
        else if (st != GSL_SUCCESS)
            status = TR_ENOPROGRESS;
    }
    if (st != GSL_EBADFUNC || it > 0) {
        memcpy(d->x, s->x->data, (size_t)k * sizeof(double));
        memcpy(d->f, s->f->data, (size_t)k * sizeof(double));
        for (i = 0; i < k; i++)
            for (j = 0; j < k; j++) d->J[i * k + j] = gsl_matrix_get(s->J, i, j);
        d->have_J = 1;
        d->J_fresh = 0;
    }
    d->fnorm = maxnorm(d->f, k);
    d->nit += it;
    switch (status) {
    case TR_OK: break;
    case TR_EMAXITER:
        tr_set_message(d,
                       "did not converge in %d iterations (hybrid; scaled residual %.3g > tol "
                       "%.3g); raise max_iter",
                       max_iter, d->fnorm, d->opt.tol);
        break;
    case TR_EMAXFEV:
        tr_set_message(d,
                       "function-evaluation limit (max_nfev = %d) reached (hybrid; scaled "
                       "residual %.3g); raise max_nfev",
                       d->opt.max_nfev, d->fnorm);
        break;
    case TR_ENONFINITE:
        tr_set_message(d, "the residual became non-finite in the hybrid iteration");
        break;
    default:
        tr_set_message(d,
                       "the hybrid (dogleg) iteration made no progress at scaled residual %.3g "
                       "(GSL: %s); the scene may have no equilibrium nearby",
                       d->fnorm, gsl_strerror(st));
    }
    return status;
}

/* Iterate from the current point until converged, a cap, or stagnation (the
 * residual fell by less than 1/ratio over the last `stall` <= TR_STALL_ITERS
 * iterations). */
static int newton_run_stall(const tr_model *m, tr_data *d, int max_iter, int stall, double ratio)
{
    int it = 0;
    double hist[TR_STALL_ITERS]; /* residual norms of the last TR_STALL_ITERS iterations */
    if (d->opt.jacobian_method == TR_JAC_HYBRID && d->hyb) return hybrid_run(m, d, max_iter);
    for (;;) {
        int status;
        if (tr_solve_test(m, d) == TR_OK) return TR_OK;
        /* creeping (tiny damped steps along a curved valley, e.g. the common-mode
         * tension of stiff tendons under twist): give up early, so that the caller's
         * continuation starts before max_iter evaluations are spent */
        if (it >= stall && d->fnorm > ratio * hist[(it - stall) % TR_STALL_ITERS]) {
            tr_set_message(d,
                           "stagnated (scaled residual %.3g > tol %.3g, down by less than "
                           "%gx in %d iterations); give a guess from a nearby solved scene",
                           d->fnorm, d->opt.tol, 1.0 / ratio, stall);
            return TR_EMAXITER;
        }
        hist[it % TR_STALL_ITERS] = d->fnorm;
        if (d->nfev >= d->opt.max_nfev) {
            tr_set_message(d,
                           "function-evaluation limit (max_nfev = %d) reached (scaled residual "
                           "%.3g > tol %.3g); raise max_nfev",
                           d->opt.max_nfev, d->fnorm, d->opt.tol);
            return TR_EMAXFEV;
        }
        if (it >= max_iter) {
            tr_set_message(d,
                           "did not converge in %d iterations (scaled residual %.3g > tol %.3g); "
                           "raise max_iter, or give a guess from a nearby solved scene",
                           max_iter, d->fnorm, d->opt.tol);
            return TR_EMAXITER;
        }
        status = tr_solve_iterate(m, d);
        it++;
        if (status < 0) return status;
    }
}

static int newton_run(const tr_model *m, tr_data *d, int max_iter)
{
    return newton_run_stall(m, d, max_iter, TR_STALL_ITERS, TR_STALL_RATIO);
}

/* Tip position (world) of the state integrated from x (one evaluation). */
static void tip_of(const tr_model *m, tr_data *d, const double *x, double p[3])
{
    double R[9], n[3], mo[3];
    if (tr_residual(m, d, x, d->ft) != TR_OK) {
        p[0] = p[1] = p[2] = NAN;
        return;
    }
    tr_state_world(m, d->y, p, R, n, mo);
}

/* Ramp *lamp (d->lam_act or d->lam_load) from its solved value to 1 with an
 * adaptive step (halve on failure, double on success) and a secant predictor. */
static int ramp(const tr_model *m, tr_data *d, double *lamp, const char *what, double dmax)
{
    const int k = d->k;
    const int iter_cap = d->opt.max_iter < TR_CONT_ITER ? d->opt.max_iter : TR_CONT_ITER;
    double lam = *lamp, dlam = TR_CONT_DLAM0 < dmax ? TR_CONT_DLAM0 : dmax, dlam_prev = 0.0;
    double tip[3], tip_new[3];
    int have_prev = 0, status, i;
    /* the tip of the solved start, to catch a load stage that jumps to another branch */
    if (lamp == &d->lam_load)
        tip_of(m, d, d->x, tip);
    else
        tip[0] = tip[1] = tip[2] = 0.0;
    while (lam < 1.0) {
        double lt;
        if (dlam > dmax) dlam = dmax;
        lt = lam + dlam > 1.0 ? 1.0 : lam + dlam;
        if (d->nfev >= d->opt.max_nfev) {
            tr_set_message(d,
                           "function-evaluation limit (max_nfev = %d) reached during continuation "
                           "at %.4g of the %s; raise max_nfev",
                           d->opt.max_nfev, lam, what);
            *lamp = lam;
            return TR_EMAXFEV;
        }
        if (d->cont_steps >= d->opt.max_continuation) {
            tr_set_message(d,
                           "continuation reached only %.4g of the %s in max_continuation = %d "
                           "steps; raise max_continuation, or the scene may have no equilibrium on "
                           "this path (e.g. buckling, or a tendon that cannot hold the load)",
                           lam, what, d->opt.max_continuation);
            *lamp = lam;
            return TR_ECONTINUATION;
        }
        memcpy(d->xs, d->x, (size_t)k * sizeof(double));
        memcpy(d->fs, d->f, (size_t)k * sizeof(double));
        if (have_prev)
            for (i = 0; i < k; i++) d->x[i] += (d->x[i] - d->xp[i]) * (lt - lam) / dlam_prev;
        *lamp = lt;
        status = tr_residual(m, d, d->x, d->f);
        d->fnorm = maxnorm(d->f, k);
        if (status == TR_OK)
            status = newton_run_stall(m, d, iter_cap, TR_CONT_STALL_ITERS, TR_CONT_STALL_RATIO);
        d->cont_steps++;
        if (status == TR_EMAXFEV) return status;
        if (status == TR_OK) {
            /* a stage whose tip jumps by more than TR_CONT_TIP_JUMP L left the branch it
             * started on (exponentially sensitive shapes can do that in one Newton
             * iteration): reject it and take a smaller step */
            if (lamp == &d->lam_load)
                tip_of(m, d, d->x, tip_new);
            else
                tip_new[0] = tip_new[1] = tip_new[2] = 0.0;
            if (lamp == &d->lam_load &&
                hypot(hypot(tip_new[0] - tip[0], tip_new[1] - tip[1]), tip_new[2] - tip[2]) >
                    TR_CONT_TIP_JUMP * m->L &&
                dlam > TR_CONT_DLAM_MIN * 4.0)
                status = TR_ENOPROGRESS;
        }
        if (status == TR_OK) {
            memcpy(tip, tip_new, sizeof tip);
            memcpy(d->xp, d->xs, (size_t)k * sizeof(double));
            dlam_prev = lt - lam;
            lam = lt;
            have_prev = 1;
            dlam = 2.0 * dlam;
        } else {
            memcpy(d->x, d->xs, (size_t)k * sizeof(double));
            memcpy(d->f, d->fs, (size_t)k * sizeof(double));
            d->fnorm = maxnorm(d->f, k);
            *lamp = lam;
            d->have_J = 0;
            have_prev = 0; /* the secant may point across a switch: predict constant */
            dlam *= 0.5;
            if (dlam < TR_CONT_DLAM_MIN) {
                tr_set_message(d,
                               "continuation stalled at %.4g of the %s (step below %g): the "
                               "scene may have no equilibrium on this path (a limit point, "
                               "buckling, a tendon that cannot hold the load, or an impossible "
                               "actuation)",
                               lam, what, TR_CONT_DLAM_MIN);
                return TR_ECONTINUATION;
            }
        }
    }
    return TR_OK;
}

/* Continuation from the unloaded straight robot: first the actuation (loads
 * off), then the loads -- the order a robot is used in, which keeps an axial
 * load on a still-straight robot from buckling it on the way. */
static int continuation_run(const tr_model *m, tr_data *d)
{
    int status;
    d->lam_act = 0.0;
    d->lam_load = 0.0;
    cold_start(m, d);
    d->have_J = 0;
    status = tr_residual(m, d, d->x, d->f);
    d->fnorm = maxnorm(d->f, d->k);
    if (status == TR_OK) status = newton_run(m, d, d->opt.max_iter);
    if (status == TR_EMAXFEV) return status;
    if (status != TR_OK) {
        tr_set_message(d, "continuation could not solve the unloaded robot: %s",
                       tr_strerror(status));
        return TR_ECONTINUATION;
    }
    status =
        ramp(m, d, &d->lam_act, "actuation (tendon displacements and tensions, loads off)", 1.0);
    if (status != TR_OK) return status;
    /* load steps of at most TR_RAMP_LOAD (scaled F L^2/EI + M L/EI) keep the path on the
     * branch that grows from the unloaded robot */
    {
        const double ls = tr_load_scale(m);
        return ramp(m, d, &d->lam_load, "loads (at full actuation)",
                    ls > TR_RAMP_LOAD ? TR_RAMP_LOAD / ls : 1.0);
    }
}

/* Continuation steps use full Newton (fresh Jacobian every iteration): a
 * Broyden Jacobian carried across a taut/slack switch misleads the step. */
static int continuation(const tr_model *m, tr_data *d)
{
    const int saved = d->opt.jacobian_method;
    int status;
    d->opt.jacobian_method = TR_JAC_NEWTON;
    status = continuation_run(m, d);
    d->opt.jacobian_method = saved;
    return status;
}

/* 1-norm condition number of d->J (inverts through the LU; k is small). */
static double jac_cond(tr_data *d)
{
    const int k = d->k;
    double nJ = 0.0, nI = 0.0;
    int i, j;
    if (k == 0) return 1.0;
    for (j = 0; j < k; j++) {
        double c = 0.0;
        for (i = 0; i < k; i++) c += fabs(d->J[i * k + j]);
        if (c > nJ) nJ = c;
    }
    if (factor(d) != 0) return INFINITY;
    for (j = 0; j < k; j++) {
        double c = 0.0;
        for (i = 0; i < k; i++) d->work[i] = (i == j);
        if (lu_solve(d, d->work, d->ft) != 0) return INFINITY;
        for (i = 0; i < k; i++) c += fabs(d->ft[i]);
        if (c > nI) nI = c;
    }
    return nJ * nI;
}

/* Step-doubling estimate of the truncation error at the current steps N and x:
 * the change of the residual (into d->f at N, d->ft at 2N) and of the scaled tip
 * state when every segment's steps are doubled, divided by (1 - 2^-p).  Returns
 * INFINITY if an integration fails. */
static double doubling_estimate(const tr_model *m, tr_data *d)
{
    const int k = d->k;
    const double order = d->opt.integrator == TR_RK4 ? 4.0 : 8.0;
    double est = 0.0;
    int status, c;
    status = tr_residual(m, d, d->x, d->f);
    d->fnorm = status == TR_OK ? maxnorm(d->f, k) : INFINITY;
    memcpy(d->ysave, d->y, (size_t)m->n_base * sizeof(double));
    d->steps_double = 1;
    if (status == TR_OK) status = tr_residual(m, d, d->x, d->ft);
    d->steps_double = 0;
    if (status != TR_OK) return INFINITY;
    for (c = 0; c < k; c++) {
        const double e = fabs(d->ft[c] - d->f[c]);
        if (!(e <= est)) est = e;
    }
    for (c = 0; c < m->n_base; c++) {
        const double e = fabs(d->y[c] - d->ysave[c]) / m->xstate_scale[c];
        if (!(e <= est)) est = e;
    }
    return est / (1.0 - pow(2.0, -order));
}

/* Richardson: the step count whose truncation error est (N / Nn)^p is
 * TR_REFINE_SAFETY tol, at least N + 1 (2N when est is not finite), capped. */
static int refined_steps(const tr_data *d, int N, double est)
{
    const double order = d->opt.integrator == TR_RK4 ? 4.0 : 8.0;
    int Nn = N + 1;
    if (isfinite(est)) {
        const double want = ceil(N * pow(est / (TR_REFINE_SAFETY * d->opt.tol), 1.0 / order));
        if (want > Nn) Nn = want < (double)TR_STEP_CAP ? (int)want : TR_STEP_CAP;
    } else {
        Nn = 2 * N;
    }
    return Nn < TR_STEP_CAP ? Nn : TR_STEP_CAP;
}

/* Verify the step count by doubling (steps = 0).  With every segment's steps
 * doubled, the change of the residual and of the tip state (scaled) is (1 - 2^-p)
 * of the truncation error at N steps (order p): that estimate of the error at N
 * is what is compared with tol.  While it is too big, the count is raised to the
 * Richardson prediction for TR_REFINE_SAFETY tol (at least N + 1 steps) and the
 * Newton iteration continues from the current point at the new count. */
static int verify_steps(const tr_model *m, tr_data *d)
{
    const int k = d->k;
    int round;
    for (round = 0; round < 16; round++) {
        const int N = d->steps;
        const double est = doubling_estimate(m, d);
        int status;
        d->truncation = est;
        if (est <= d->opt.tol) {
            /* N steps verified; the polish that follows may still reduce the
             * residual at N (a converged residual near tol is not polished yet) */
            d->steps_moved = 1;
            return TR_OK;
        }
        if (N >= TR_STEP_CAP) {
            tr_set_message(d,
                           "converged, but the truncation estimate %.3g stayed above tol %.3g "
                           "at %d steps; use a higher-order integrator or a looser tol",
                           est, d->opt.tol, N);
            return TR_TRUNCATION;
        }
        d->steps = refined_steps(d, N, est);
        status = tr_residual(m, d, d->x, d->f);
        d->fnorm = maxnorm(d->f, k);
        /* (no stagnation test: the point is converged at N steps already) */
        if (status == TR_OK)
            status = newton_run_stall(m, d, d->opt.max_iter, TR_STALL_ITERS, INFINITY);
        if (status != TR_OK) return status;
    }
    return TR_TRUNCATION;
}

/* Polish a converged point: if the Newton step from it (with the final Jacobian)
 * is still large -- a small residual that does not pin the unknowns, as for stiff
 * antagonistic tendons on an inextensible backbone -- take full Newton steps while
 * they do not increase the residual. */
static void polish(const tr_model *m, tr_data *d)
{
    const int k = d->k;
    int p, i;
    for (p = 0; p < TR_POLISH_STEPS; p++) {
        double big = 0.0;
        if (factor(d) != 0 || lu_solve(d, d->f, d->dx) != 0) return;
        for (i = 0; i < k; i++) {
            const double r = fabs(d->dx[i]) / (fabs(d->x[i]) > 1.0 ? fabs(d->x[i]) : 1.0);
            if (r > big) big = r;
            d->xt[i] = d->x[i] - d->dx[i];
        }
        /* after the step doubling moved to 2N steps the residual there (the truncation
         * estimate) is polished away too */
        if (!(big > TR_POLISH_XTOL_FACTOR * d->opt.tol) &&
            !(d->steps_moved && d->fnorm > TR_POLISH_RES_FACTOR * d->opt.tol))
            return;
        if (tr_residual(m, d, d->xt, d->ft) != TR_OK) return;
        if (!(maxnorm(d->ft, k) <= (d->fnorm > d->opt.tol ? d->fnorm : d->opt.tol))) return;
        memcpy(d->x, d->xt, (size_t)k * sizeof(double));
        memcpy(d->f, d->ft, (size_t)k * sizeof(double));
        d->fnorm = maxnorm(d->f, k);
        d->nit++;
    }
}

/* Automatic initial step count: the fixed minimum, or enough steps to resolve the
 * boundary layers of width L / lambda that a load of magnitude F makes, lambda =
 * L sqrt(F / EI) (TR_AUTO_PER_LAMBDA steps per unit lambda). */
static int auto_steps(const tr_model *m, const tr_data *d)
{
    const int base = d->opt.integrator == TR_RK4 ? TR_AUTO_RK4 : TR_AUTO_RK8;
    const double per = d->opt.integrator == TR_RK4 ? 4.0 * TR_AUTO_PER_LAMBDA : TR_AUTO_PER_LAMBDA;
    double F = m->L * tru_norm3(m->dist), lam;
    int b, n;
    for (b = 1; b <= m->nseg; b++) F += tru_norm3(m->bpF + 3 * b);
    lam = m->L * sqrt(F / m->EI);
    n = (int)ceil(fmin(per * lam, (double)TR_AUTO_MAX));
    return n > base ? n : base;
}

int tr_solve(const tr_model *m, tr_data *d, const double *guess, const double *jac)
{
    int status, forced = 0;
    d->nit = d->nfev = d->njev = d->cont_steps = 0;
    d->steps_moved = 0;
    d->steps_double = 0;
    d->message[0] = '\0';
    d->lam_act = d->lam_load = 1.0;
    d->truncation = NAN;
    d->jacobian_cond = NAN;
    d->probe_bp = -1;
    d->steps = d->opt.steps > 0 ? d->opt.steps : auto_steps(m, d);
    if (d->model != m) {
        tr_set_message(d, "workspace was allocated for a different model");
        return d->status = TR_EINVAL;
    }
    if (m->scene_status != TR_OK) {
        int i;
        tr_set_message(d, "%s", m->scene_message);
        for (i = 0; i < 19 * d->nnode; i++) d->s[i] = NAN;
        for (i = 0; i < 3 * m->nt; i++) d->tension[i] = NAN;
        for (i = 0; i < d->k; i++) d->x[i] = NAN;
        d->have_J = 0;
        for (i = 0; i < d->k * d->k; i++) d->J[i] = NAN;
        return d->status = m->scene_status;
    }
    status = tr_solve_init(m, d, guess, jac);
    if (status == TR_EINVAL) return d->status = status;
    if (status == TR_OK && !guess && d->opt.continuation && d->opt.max_continuation > 0 &&
        tr_load_scale(m) > TR_DIRECT_LOAD_MAX) {
        /* large loads from a cold start: a direct Newton iteration can land on a looped,
         * unstable equilibrium (buckled-through elastica); follow the load path from
         * the unloaded robot instead */
        status = TR_ECONTINUATION;
        forced = 1;
        tr_set_message(d, "large loads (scaled %.3g > %g): solved by continuation",
                       tr_load_scale(m), TR_DIRECT_LOAD_MAX);
    } else if (status == TR_OK) {
        status = newton_run(m, d, d->opt.max_iter);
    }
    if (status < 0 && status != TR_EMAXFEV && d->opt.continuation && d->opt.max_continuation > 0) {
        char first[TR_MSGLEN];
        int st2;
        memcpy(first, d->message, TR_MSGLEN);
        st2 = continuation(m, d);
        if (st2 == TR_OK) {
            status = TR_OK;
        } else {
            char second[TR_MSGLEN];
            memcpy(second, d->message, TR_MSGLEN);
            tr_set_message(d, "%s; then %s", first, second);
            status = st2 == TR_EMAXFEV ? st2 : TR_ECONTINUATION;
            if (forced && st2 != TR_EMAXFEV) {
                /* the load path stalled (a limit point: snap-through): an equilibrium
                 * may still exist off that path; a direct cold solve may find it */
                int st3;
                char both[TR_MSGLEN];
                memcpy(both, d->message, TR_MSGLEN);
                d->lam_act = d->lam_load = 1.0;
                st3 = tr_solve_init(m, d, NULL, NULL);
                if (st3 == TR_OK) st3 = newton_run(m, d, d->opt.max_iter);
                if (st3 == TR_OK) {
                    status = TR_OFFPATH;
                    tr_set_message(d,
                                   "converged by a direct solve, but load continuation from the "
                                   "unloaded robot stalled (%s): this equilibrium may not be the "
                                   "one reached by loading the robot (a limit point / "
                                   "snap-through lies on the path)",
                                   second);
                } else {
                    tr_set_message(d, "%s; a direct solve did not converge either", both);
                }
            }
        }
    }
    if (status >= 0 && d->opt.steps == 0 && d->opt.integrator != TR_ADAPTIVE) {
        const int vs = verify_steps(m, d);
        if (vs != TR_OK) status = vs;
    }
    /* A cold solve returns a fresh finite-difference Jacobian at the solution (the
     * Broyden-updated one is accurate only along recent steps): it makes the
     * condition estimate meaningful and warm starts from it Newton-fast.  Warm
     * solves keep the updated one (it came from a nearby fresh one). */
    if (status >= 0 && !jac && !d->J_fresh && d->k > 0) {
        const int fs = fd_jacobian(m, d);
        if (fs != TR_OK) d->have_J = 0;
    }

    if (status >= 0 && d->have_J) polish(m, d);
    d->jacobian_cond = d->have_J ? jac_cond(d) : NAN;
    if (status >= 0 && d->jacobian_cond > TR_COND_SINGULAR) {
        status = TR_ILLCONDITIONED;
        tr_set_message(d,
                       "converged, but the Jacobian is nearly singular (condition %.3g): the "
                       "tendon tensions are poorly determined; if opposing inextensible tendons "
                       "act on an inextensible backbone the problem is statically indeterminate: "
                       "give the tendons a finite EA or the backbone an extension stiffness",
                       d->jacobian_cond);
    } else if (status < 0 && d->jacobian_cond > TR_COND_SINGULAR && m->ndisp >= 2) {
        char first[TR_MSGLEN];
        memcpy(first, d->message, TR_MSGLEN);
        tr_set_message(d,
                       "%s; the Jacobian is nearly singular (condition %.3g): the tendon "
                       "tensions may be statically indeterminate (give the tendons a finite EA "
                       "or the backbone an extension stiffness)",
                       first, d->jacobian_cond);
    }
    if (status < 0 && status != TR_EMAXFEV && m->ndisp >= 2) {
        /* stiff tendons sharing a tension level (S4/S5): that level is fixed only by
         * their stretch, a near-null direction of the Jacobian (singular value ~
         * EI/(r^2 EA)) along which second-order shape terms spoil the Newton step */
        double stiff = 0.0;
        int i;
        for (i = 0; i < m->nt; i++) {
            const tr_tendon *t = m->tendon + i;
            const double ratio = t->b * t->b * t->EA / m->EI;
            if (t->control == TR_DISPLACEMENT && isfinite(t->EA) && ratio > stiff) stiff = ratio;
        }
        if (stiff > TR_STIFF_HINT) {
            char first[TR_MSGLEN];
            memcpy(first, d->message, TR_MSGLEN);
            tr_set_message(d,
                           "nearly inextensible tendons (r^2 EA/EI up to %.3g: the tension "
                           "level they share is set only by their stretch, poorly resolved by "
                           "Newton; try a softer EA, or a guess solved with softer tendons): %s",
                           stiff, first);
        }
    }
    d->residual_norm = d->fnorm;
    d->lam_act = d->lam_load = 1.0;
    {
        const int rs = tr_record(m, d);
        if (rs != TR_OK && status >= 0) {
            status = rs;
            tr_set_message(d, "the recording pass failed: %s", tr_strerror(rs));
        }
    }
    if (status == TR_OK)
        tr_set_message(d, "converged in %d iterations (scaled residual %.3g <= tol %.3g)", d->nit,
                       d->residual_norm, d->opt.tol);
    else if (status == TR_TRUNCATION && d->message[0] == '\0')
        tr_set_message(d, "%s", tr_strerror(status));
    return d->status = status;
}

/* ------------------------------------------------------------- recording */
static void store_node(const tr_model *m, tr_data *d, int j, const double *y)
{
    tr_state_world(m, y, d->pos + 3 * j, d->rot + 9 * j, d->force + 3 * j, d->moment + 3 * j);
}

/* Integrate a span [s0, s1] of segment k in the recording pass with at least the
 * accuracy of the shooting steps.  Fixed-step rk8: where nodes are dense, a few
 * classical RK4 steps of at most an eighth of the shooting step cost less than
 * one 13-stage rk8 step and stay as accurate (error ~ (h/8)^4 against h^8 for
 * the curvatures of a robot); where nodes are sparse, rk8 at the shooting step. */
static int record_span(const tr_model *m, tr_data *d, double s0, double s1, int k, double *y,
                       int allow_rk4, int *used_rk4)
{
    const double len = s1 - s0;
    const double h = (m->bp[k + 1] - m->bp[k]) / tr_segment_steps(m, d, k);
    int n8, n4, status;
    if (!(len > 0.0)) return TR_OK;
    n8 = (int)ceil(len / h - 1e-9);
    if (n8 < 1) n8 = 1;
    if (d->opt.integrator != TR_RK8) return tr_integrate(m, d, s0, s1, n8, y);
    n4 = (int)ceil(len / fmin(h / TR_RECORD_RK4_FRACTION, m->L / TR_RECORD_RK4_MIN_STEPS) - 1e-9);
    if (n4 < 1) n4 = 1;
    if (!allow_rk4 || 4 * n4 >= 13 * n8) return tr_integrate(m, d, s0, s1, n8, y);
    *used_rk4 = 1;
    d->opt.integrator = TR_RK4;
    status = tr_integrate(m, d, s0, s1, n4, y);
    d->opt.integrator = TR_RK8;
    return status;
}

/* Restart the recording at shooting node j from its unknowns; the recording
 * layout has a path-length slot per tendon: those of displacement-controlled
 * tendons come from the node, the others keep integrating (they are continuous). */
static void rec_restart(const tr_model *m, tr_data *d, int j, double *y)
{
    const int o = node_off(m, j), lenbase = m->n_base;
    int c, i;
    for (c = 0; c < m->n_base; c++) y[c] = d->x[o + c] * node_scale(m, c);
    for (i = 0; i < m->nt; i++) {
        const tr_tendon *t = &m->tendon[i];
        if (t->len_index >= 0) y[lenbase + i] = d->x[o + m->n_base + t->len_index] * m->len_s;
    }
}

static int record_pass(const tr_model *m, tr_data *d, int allow_rk4, int *used)
{
    const double eps = 1e-12 * m->L;
    const int nn = d->nnode, lenbase = m->planar ? TR_YP_LEN : TR_Y_LEN;
    double *y = d->y, scur = 0.0;
    int j, k = 0, status = TR_OK, i, used_rk4 = 0;

    d->rec = 1;
    set_tensions(m, d, d->x);
    init_state(m, d, d->x, y, m->n_states_rec);
    for (j = 0; j < nn && status == TR_OK; j++) {
        const double sj = d->s[j];
        while (k < m->nseg - 1 && sj > m->bp[k + 1] + eps && status == TR_OK) {
            d->seg = k;
            status = record_span(m, d, scur, m->bp[k + 1], k, y, allow_rk4, &used_rk4);
            apply_jump(m, d, k + 1, y);
            if (m->bp_node[k + 1] > 0) rec_restart(m, d, m->bp_node[k + 1], y);
            scur = m->bp[k + 1];
            k++;
        }
        if (status != TR_OK) break;
        d->seg = k;
        if (k < m->nseg - 1 && fabs(sj - m->bp[k + 1]) <= eps) {
            const int pre = (j + 1 < nn && fabs(d->s[j + 1] - sj) <= eps);
            status = record_span(m, d, scur, m->bp[k + 1], k, y, allow_rk4, &used_rk4);
            scur = m->bp[k + 1];
            if (!pre) {
                apply_jump(m, d, k + 1, y);
                if (m->bp_node[k + 1] > 0) rec_restart(m, d, m->bp_node[k + 1], y);
                k++;
            }
        } else {
            const double se = sj > m->bp[k + 1] ? m->bp[k + 1] : sj;
            if (se > scur) status = record_span(m, d, scur, se, k, y, allow_rk4, &used_rk4);
            if (se > scur) scur = se;
        }
        store_node(m, d, j, y);
    }
    while (k < m->nseg && status == TR_OK) {
        d->seg = k;
        if (m->bp[k + 1] > scur)
            status = record_span(m, d, scur, m->bp[k + 1], k, y, allow_rk4, &used_rk4);
        scur = m->bp[k + 1];
        if (k + 1 < m->nseg) {
            apply_jump(m, d, k + 1, y);
            if (m->bp_node[k + 1] > 0) rec_restart(m, d, m->bp_node[k + 1], y);
        }
        k++;
    }
    d->nfev++;
    d->rec = 0;
    for (i = 0; i < m->nt; i++) {
        const tr_tendon *t = &m->tendon[i];
        d->tension[i] = d->tau[i];
        d->slack[i] = d->beta[i];
        if (t->control == TR_DISPLACEMENT)
            d->displacement[i] = t->value;
        else
            d->displacement[i] = t->rest_dev +
                                 (isfinite(t->EA) ? d->tau[i] / t->EA : 0.0) * t->rest -
                                 y[lenbase + i];
    }
    *used = used_rk4;
    if (status != TR_OK) {
        /* nothing stale is handed back: the recorded states (pos, rot, force, moment:
         * 18 per node, contiguous after s in one block, see tr_data_alloc) become NaN;
         * the node arc lengths d->s are inputs of the next recording pass and stay */
        for (j = 0; j < 18 * nn; j++) d->pos[j] = NAN;
    }
    return status;
}

/* The recording pass; if it took RK4 shortcuts (dense nodes), its tip is checked
 * against the shooting integration's tip: redone at the shooting steps when they
 * differ grossly (> TR_RECORD_GROSS, scaled), else the tip node is replaced by the
 * shooting tip. */
int tr_record(const tr_model *m, tr_data *d)
{
    int used = 0, status = record_pass(m, d, 1, &used);
    if (status == TR_OK && used) {
        double diff = 0.0;
        int i;
        memcpy(d->ysave, d->y, (size_t)m->n_base * sizeof(double));
        status = tr_residual(m, d, d->x, d->ft);
        if (status != TR_OK) return record_pass(m, d, 0, &used);
        for (i = 0; i < m->n_base; i++) {
            const double e = fabs(d->ysave[i] - d->y[i]) / m->xstate_scale[i];
            if (e > diff) diff = e;
        }
        if (!(diff <= TR_RECORD_GROSS)) return record_pass(m, d, 0, &used);
        /* the tip node carries the shooting solution itself (the one the residual
         * and the tolerance refer to); the RK4 nodes before it agree to ~1e-9 */
        if (d->nnode > 0 && fabs(d->s[d->nnode - 1] - m->L) <= 1e-12 * m->L)
            store_node(m, d, d->nnode - 1, d->y);
    }
    return status;
}

/* -------------------------------------------------------------- compliance */
int tr_compliance(const tr_model *m, tr_data *d, double s_probe, double C[36])
{
    const int k = d->k;
    const double hx = TR_CD_H;
    int pb = -1, b, i, j, q, status;
    double R0[9];
    for (b = 1; b <= m->nseg; b++)
        if (fabs(m->bp[b] - s_probe) <= 1e-12 * m->L) pb = b;
    if (pb < 0) {
        tr_set_message(d,
                       "compliance: s = %g m is not a breakpoint of the model (add a zero "
                       "point load there)",
                       s_probe);
        return TR_EINVAL;
    }
    if (m->planar) {
        tr_set_message(d, "compliance needs the spatial formulation (force_spatial)");
        return TR_EINVAL;
    }
    d->probe_bp = pb;
    memset(d->probe, 0, sizeof d->probe);
    d->lam_act = d->lam_load = 1.0;
    status = tr_residual(m, d, d->x, d->f);
    if (status != TR_OK) goto done;
    memcpy(R0, d->probe_state + 3, sizeof R0);
    /* d(residual)/dx and d(pose at probe)/dx, central differences */
    for (j = 0; j < k; j++) {
        double Yp[12];
        memcpy(d->xt, d->x, (size_t)k * sizeof(double));
        d->xt[j] = d->x[j] + hx;
        status = tr_residual(m, d, d->xt, d->ft);
        if (status != TR_OK) goto done;
        memcpy(Yp, d->probe_state, sizeof Yp);
        for (i = 0; i < k; i++) d->work[i] = d->ft[i];
        d->xt[j] = d->x[j] - hx;
        status = tr_residual(m, d, d->xt, d->ft);
        if (status != TR_OK) goto done;
        for (i = 0; i < k; i++) d->J[i * k + j] = (d->work[i] - d->ft[i]) / (2.0 * hx);
        {
            double dR[9], W[9];
            for (i = 0; i < 3; i++) d->Yx[i * k + j] = (Yp[i] - d->probe_state[i]) / (2.0 * hx);
            for (i = 0; i < 9; i++) dR[i] = (Yp[3 + i] - d->probe_state[3 + i]) / (2.0 * hx);
            /* W = dR R0^T (skew): dtheta = vee(W) */
            for (i = 0; i < 3; i++)
                for (q = 0; q < 3; q++)
                    W[3 * i + q] = dR[3 * i] * R0[3 * q] + dR[3 * i + 1] * R0[3 * q + 1] +
                                   dR[3 * i + 2] * R0[3 * q + 2];
            d->Yx[3 * k + j] = 0.5 * (W[7] - W[5]);
            d->Yx[4 * k + j] = 0.5 * (W[2] - W[6]);
            d->Yx[5 * k + j] = 0.5 * (W[3] - W[1]);
        }
    }
    d->njev++;
    /* d(residual)/d(probe load) */
    for (q = 0; q < 6; q++) {
        const double hp = hx * (q < 3 ? m->F_s : m->M_s);
        memset(d->probe, 0, sizeof d->probe);
        d->probe[q] = hp;
        status = tr_residual(m, d, d->x, d->ft);
        if (status != TR_OK) goto done;
        for (i = 0; i < k; i++) d->work[i] = d->ft[i];
        d->probe[q] = -hp;
        status = tr_residual(m, d, d->x, d->ft);
        if (status != TR_OK) goto done;
        for (i = 0; i < k; i++) d->Fp[i * 6 + q] = (d->work[i] - d->ft[i]) / (2.0 * hp);
    }
    memset(d->probe, 0, sizeof d->probe);
    if (factor(d) != 0) {
        tr_set_message(d, "compliance: the Jacobian at the solution is singular");
        status = TR_ESINGULAR;
        goto done;
    }
    /* du/dp = -J^-1 Fp; C = Yx du/dp */
    for (q = 0; q < 6; q++) {
        for (i = 0; i < k; i++) d->work[i] = -d->Fp[i * 6 + q];
        if (lu_solve(d, d->work, d->ft) != 0) {
            status = TR_ESINGULAR;
            goto done;
        }
        for (i = 0; i < 6; i++) {
            double c = 0.0;
            for (j = 0; j < k; j++) c += d->Yx[i * k + j] * d->ft[j];
            C[6 * i + q] = c;
        }
    }
    status = TR_OK;
done:
    d->probe_bp = -1;
    memset(d->probe, 0, sizeof d->probe);
    if (status != TR_OK && d->message[0] == '\0')
        tr_set_message(d, "compliance failed: %s", tr_strerror(status));
    return status;
}
