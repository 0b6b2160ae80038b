/*
 * tr_verify.c -- the automatic step count (steps = 0): the initial count from the
 * scene's load scale, its verification by step doubling with Richardson
 * refinement, and the polish of a converged point.
 */
#include <math.h>
#include <string.h>

#include "tendonrod.h"
#include "tr_internal.h"
#include "tru_math.h"

/* A truncation estimate no larger than tol, or than the round-off floor of the two
 * residuals it differences (tr_roundoff_floor each, divided by 1 - 2^-p as the estimate
 * is; a floor below TR_ROUNDOFF_HINT, as tr_solve_test's): below that, the estimate
 * cannot be told from zero. */
static int estimate_within(const tr_model *m, const tr_data *d, double est, double tol)
{
    const double order = d->opt.integrator == TR_RK4 ? 4.0 : 8.0;
    const double fl = tr_roundoff_floor(m, d);
    return est <= tol || (est <= 2.0 * fl / (1.0 - pow(2.0, -order)) && fl <= TR_ROUNDOFF_HINT);
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
    if (tr_holds_end_state(d, d->x)) {
        /* the last evaluation was at x at N steps: its end state and residual */
        memcpy(d->f, d->f_of_y, (size_t)k * sizeof(double));
        status = TR_OK;
    } else {
        status = tr_residual(m, d, d->x, d->f);
    }
    d->fnorm = status == TR_OK ? tru_maxnorm(d->f, k) : INFINITY;
    memcpy(d->ysave, d->y, (size_t)m->n_states * sizeof(double));
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
    /* y holds the end state at N steps again (the solution's, for tr_tip_state) */
    tr_restore_end_state(m, d, d->x, d->f);
    return est / (1.0 - pow(2.0, -order));
}

int tr_verify_fixed(const tr_model *m_, tr_data *d, int status)
{
    const tr_model *m = TR_IN(m_, d);
    const int finishing = d->finishing;
    double est;
    if (status < 0 || d->opt.steps <= 0 || d->opt.integrator == TR_ADAPTIVE) return status;
    /* two evaluations, paid beyond the budget like the final outputs (an interrupt still
     * stops them) */
    d->finishing = 1;
    est = doubling_estimate(m, d);
    d->finishing = finishing;
    if (d->stop) return status;
    d->truncation = est;
    if (status == TR_OK && !estimate_within(m, d, est, TR_FIXED_TRUNC_WARN * d->opt.tol)) {
        tr_set_message(d,
                       "converged, but the truncation error at the fixed %d steps is estimated "
                       "at %.3g (scaled, by step doubling), above %g x tol: the answer is "
                       "only that accurate; raise Options.steps, use a higher-order "
                       "integrator, or let the solver choose the steps (steps = 0)",
                       d->steps, est, TR_FIXED_TRUNC_WARN);
        return TR_TRUNCATION;
    }
    return status;
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
int tr_verify_steps(const tr_model *m_, tr_data *d)
{
    const tr_model *m = TR_IN(m_, d);
    const int k = d->k;
    int round, c;
    for (round = 0; round < TR_REFINE_ROUNDS; round++) {
        const int N = d->steps;
        const double est = doubling_estimate(m, d);
        int status;
        if (d->stop) return d->stop;
        d->truncation = est;
        if (estimate_within(m, d, est, d->opt.tol)) {
            /* N steps verified; the polish that follows may still reduce the
             * residual at N (a converged residual near tol is not polished yet) */
            d->steps_moved = 1;
            memcpy(d->x_ver, d->x, (size_t)k * sizeof(double));
            d->est_ver = est;
            d->steps_ver = N;
            d->have_ver = 1;
            for (c = 0; c < m->nt; c++) d->val_ver[c] = m->tendon[c].value;
            d->have_val_ver = 1;
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
        d->fnorm = tru_maxnorm(d->f, k);
        /* (no stagnation test: the point is converged at N steps already) */
        if (status == TR_OK)
            status = tr_newton_run(m, d, d->opt.max_iter, TR_STALL_ITERS, INFINITY);
        if (status != TR_OK) return status;
    }
    return TR_TRUNCATION;
}

double tr_rel_move(const double *x, const double *x0, int k)
{
    double delta = 0.0;
    int i;
    for (i = 0; i < k; i++) {
        const double a = fabs(x0[i]);
        const double e = fabs(x[i] - x0[i]) / (a > 1.0 ? a : 1.0);
        if (!(e <= delta)) delta = e;
    }
    return delta;
}

/* A verification at x_v (truncation estimate e_v, N steps) vouches for a solution x at
 * the same N that moved delta = max_i |x_i - x_v,i| / max(1, |x_v,i|) from it, when
 * delta <= TR_CARRY_MAX_MOVE and TR_CARRY_SAFETY e_v (1 + delta)^(p+1) <= tol.  The
 * truncation error of an order-p method is ~ (h |u|)^(p+1) with u the curvature, which
 * the scaled moments carry (O(1) for an O(1) bend), so a relative change delta of the
 * unknowns grows it by about (1 + delta)^(p+1); that bound, with the factor of safety,
 * is reported as the truncation estimate.  A sweep of small steps re-verifies once its
 * unknowns drift that far from the last verification. */
int tr_verify_carried(const tr_model *m_, tr_data *d)
{
    const tr_model *m = TR_IN(m_, d);
    const double order = d->opt.integrator == TR_RK4 ? 4.0 : 8.0;
    double delta = 0.0, bound;
    int i;
    if (!d->have_ver || d->steps_ver != d->steps || !isfinite(d->est_ver)) return 0;
    delta = tr_rel_move(d->x, d->x_ver, d->k);
    /* a prescribed tension moves the state without moving the unknowns (the base reaction
     * balances the external loads whatever the tensions): its move counts too, scaled by
     * the tension scale */
    for (i = 0; i < m->nt; i++) {
        double a, e;
        if (m->tendon[i].control != TR_TENSION) continue;
        if (!d->have_val_ver) return 0;
        a = fabs(d->val_ver[i]) / m->tau_s;
        e = fabs(m->tendon[i].value - d->val_ver[i]) / m->tau_s / (a > 1.0 ? a : 1.0);
        if (!(e <= delta)) delta = e;
    }
    if (!(delta <= TR_CARRY_MAX_MOVE)) return 0;
    bound = TR_CARRY_SAFETY * d->est_ver * pow(1.0 + delta, order + 1.0);
    if (!(bound <= d->opt.tol)) return 0;
    d->truncation = bound;
    d->ver_carried = 1;
    return 1;
}

/* Polish a converged point: if the Newton step from it (with the final Jacobian)
 * is still large -- a small residual that does not pin the unknowns, as for stiff
 * antagonistic tendons on an inextensible backbone -- take full Newton steps while
 * they do not increase the residual. */
void tr_polish(const tr_model *m_, tr_data *d)
{
    const tr_model *m = TR_IN(m_, d);
    const int k = d->k;
    int p, i;
    for (p = 0; p < TR_POLISH_STEPS; p++) {
        double big = 0.0;
        if (tr_lu_factor(d) != 0 || tr_lu_solve(d, d->f, d->dx) != 0) return;
        for (i = 0; i < k; i++) {
            const double r = fabs(d->dx[i]) / (fabs(d->x[i]) > 1.0 ? fabs(d->x[i]) : 1.0);
            if (r > big) big = r;
            d->xt[i] = d->x[i] - d->dx[i];
        }
        /* after the step verification, a residual left near tol at the verified
         * step count is polished too; the first step is taken when asked (polish_once) */
        if (!(big > TR_POLISH_XTOL_FACTOR * d->opt.tol) &&
            !(d->steps_moved && d->fnorm > TR_POLISH_RES_FACTOR * d->opt.tol) &&
            !(d->polish_once && p == 0 && big > 0.0))
            return;
        if (tr_residual(m, d, d->xt, d->ft) != TR_OK) return;
        if (!(tru_maxnorm(d->ft, k) <= (d->fnorm > d->opt.tol ? d->fnorm : d->opt.tol))) return;
        memcpy(d->x, d->xt, (size_t)k * sizeof(double));
        memcpy(d->f, d->ft, (size_t)k * sizeof(double));
        d->fnorm = tru_maxnorm(d->f, k);
        d->nit++;
    }
}

/* Automatic initial step count: the fixed minimum, or enough steps to resolve the
 * boundary layers of width L / lambda that a load of magnitude F makes, lambda =
 * L sqrt(F / EI) (TR_AUTO_PER_LAMBDA steps per unit lambda), or the tendons' own
 * curling (TR_AUTO_PER_TURN of that per radian), or a frictional tendon's tension change. */
int tr_auto_steps(const tr_model *m_, const tr_data *d)
{
    const tr_model *m = TR_IN(m_, d);
    const int base = d->opt.integrator == TR_RK4 ? TR_AUTO_RK4 : TR_AUTO_RK8;
    const double per = d->opt.integrator == TR_RK4 ? 4.0 * TR_AUTO_PER_LAMBDA : TR_AUTO_PER_LAMBDA;
    double F = m->L * tru_norm3(m->dist), lam, turn = 0.0, g = 0.0;
    int b, n, i;
    for (b = 1; b <= m->nseg; b++) F += tru_norm3(m->bpF + 3 * b);
    if (m->has_pdist)
        for (b = 0; b < m->nseg; b++)
            F += (m->bp[b + 1] - m->bp[b]) * tru_norm3(m->seg_pdist + 3 * b);
    lam = m->L * sqrt(F / m->EI);
    n = (int)ceil(fmin(per * lam, (double)TR_AUTO_MAX));
    /* a tendon turns the rod by about tau r l / EI for a tension tau over its length l,
     * q / r for a retraction q; a frictional one changes its tension like e^(mu theta)
     * over that turning */
    for (i = 0; i < m->nt; i++) {
        const tr_tendon *t = &m->tendon[i];
        const double r = fmax(fabs(t->b), fabs(t->b + t->a * t->t));
        double th;
        if (!(r > 0.0)) continue;
        th = t->control == TR_DISPLACEMENT ? fabs(t->value) / r : fabs(t->value) * r * t->t / m->EI;
        if (isfinite(th)) turn += th;
    }
    g = tr_friction_exponent(m);
    n = (int)fmax(n, ceil(fmin(per * TR_AUTO_PER_TURN * turn, (double)TR_AUTO_MAX)));
    if (m->nfric) n = (int)fmax(n, ceil(fmin(per * TR_AUTO_PER_FRIC * g, (double)TR_AUTO_MAX)));
    return n > base ? n : base;
}
