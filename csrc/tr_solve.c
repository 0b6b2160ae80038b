/*
 * tr_solve.c -- the one-call driver, as a list of stages: solve() below runs them in
 * order, each a function that returns the status it was given when it does not apply
 * (begin, direct, continuation, confirm, finer steps, shared tension level, branch,
 * verify, past the centre, condition, shared level resolved, stop, diagnose, record).
 * csrc/README.md describes each stage (tools/check_house.py checks that every function
 * solve() calls is named there).  A work budget or an interrupt (tr_poll.c) ends the
 * solve after the stage it stops.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "tendonrod.h"
#include "tr_internal.h"
#include "tru_math.h"

static int solve_begin(const tr_model *m, tr_data *d, const tr_verified *v)
{
    int i, steps = d->opt.steps;
    /* automatic steps: from the guess's verified count, else the scene's estimate */
    if (steps == 0) {
        steps =
            v && v->steps > 0 && d->opt.integrator != TR_ADAPTIVE ? v->steps : tr_auto_steps(m, d);
        if (steps > TR_STEP_CAP) steps = TR_STEP_CAP;
    }
    tr_solve_reset(m, d, steps);
    d->watch_have = 0;
    d->shared_mode = 0;
    if (!TR_OWNS(m, d)) {
        tr_set_message(d, "workspace was allocated for a different model");
        return TR_EINVAL;
    }
    if (m->scene_status == TR_OK) return TR_OK;
    /* nothing stale is handed back: the recorded states (pos, rot, force, moment, 18
     * per node, contiguous in one block) and the tendon outputs become NaN; the node
     * arc lengths d->s stay (inputs of the next recording pass) */
    tr_set_message(d, "%s", m->scene_message);
    for (i = 0; i < 18 * d->nnode; i++) d->pos[i] = NAN;
    for (i = 0; i < 18; i++) d->tip[i] = NAN;
    for (i = 0; i < 3 * m->nt; i++) d->tension[i] = NAN;
    for (i = 0; i < d->k; i++) d->x[i] = NAN;
    d->have_J = 0;
    for (i = 0; i < d->k * d->k; i++) d->J[i] = NAN;
    return m->scene_status;
}

/* Start from the last successful solve of this workspace: its unknowns (node unknowns
 * included), Jacobian and verified step count. */
static int init_from_last(const tr_model *m, tr_data *d)
{
    const int k = d->k;
    int status;
    memcpy(d->x, d->x_last, (size_t)k * sizeof(double));
    memcpy(d->J, d->J_last, (size_t)k * k * sizeof(double));
    d->have_J = 1;
    d->J_fresh = d->J_refresh = 0;
    if (d->opt.steps == 0 && d->opt.integrator != TR_ADAPTIVE) d->steps = d->steps_last;
    status = tr_residual(m, d, d->x, d->f);
    d->fnorm = tru_maxnorm(d->f, k);
    return status;
}

/* A cold start with large loads goes by the load path from the unloaded robot (the
 * continuation stage, forced): why, in the message. */
static int direct_fallback(const tr_model *m, tr_data *d, int *forced, const char *why)
{
    *forced = 1;
    tr_set_message(d, "large loads (scaled %.3g > %g)%s: solved by continuation", tr_load_scale(m),
                   TR_DIRECT_LOAD_MAX, why);
    return TR_ECONTINUATION;
}

static int solve_direct(const tr_model *m, tr_data *d, const double *guess, const double *jac,
                        int from_last, int *forced)
{
    int status = from_last ? init_from_last(m, d) : tr_solve_init(m, d, guess, jac);
    *forced = 0;
    d->direct_try = 0;
    if (status != TR_OK) return status;
    if (guess || from_last) {
        /* the start, for a continuation from the guess (tr_branch.c) */
        double R[9], n[3], mo[3];
        memcpy(d->x_guess, d->x, (size_t)d->k * sizeof(double));
        memcpy(d->f_guess, d->f, (size_t)d->k * sizeof(double));
        tr_state_world(m, d->y, d->tip_guess, R, n, mo);
    }
    if (!guess && !from_last && d->opt.continuation && d->opt.max_continuation > 0 &&
        tr_load_scale(m) > TR_DIRECT_LOAD_MAX) {
        /* large loads from a cold start: a direct Newton iteration can land on a looped,
         * unstable elastica.  With the stability verdict on, a short direct try comes
         * first and stands only if the verdict calls its answer stable (tr_branch);
         * otherwise, and without the verdict, the load path from the unloaded robot */
        const double g = tr_shooting_growth(m); /* of the workspace's loads */
        if (!d->opt.accept_unstable && !d->is_confirm &&
            tr_load_scale(m) - g * g <= TR_DIRECT_TRY_SCALE) {
            status = tr_newton_run(m, d, TR_DIRECT_TRY_ITER, TR_DIRECT_TRY_STALL, TR_STALL_RATIO);
            if (status == TR_OK) {
                d->direct_try = 1;
                return TR_OK;
            }
            if (status == TR_EMAXFEV || d->stop) return status;
            return direct_fallback(m, d, forced, " and direct Newton did not converge");
        }
        return direct_fallback(m, d, forced, "");
    }
    return tr_newton_run(m, d, d->opt.max_iter, TR_STALL_ITERS, TR_STALL_RATIO);
}

static int solve_continuation(const tr_model *m, tr_data *d, int status, int forced)
{
    char first[TR_MSGLEN], second[TR_MSGLEN], both[TR_MSGLEN];
    int st2, st3;
    if (!(status < 0 && status != TR_EMAXFEV && !d->stop && d->opt.continuation &&
          d->opt.max_continuation > 0))
        return status;
    memcpy(first, d->message, TR_MSGLEN);
    st2 = tr_continuation(m, d);
    if (st2 == TR_OK) {
        d->via_path = 1;
        return TR_OK;
    }
    memcpy(second, d->message, TR_MSGLEN);
    if (strcmp(first, second) == 0) /* the same cause both ways: said once */
        tr_set_message(d, "%s (directly, and again along the load path)", first);
    else
        tr_set_message(d, "%s; then %s", first, second);
    if (st2 == TR_EMAXFEV || d->stop) return st2;
    if (!forced) return TR_ECONTINUATION;
    /* the load path stalled (a limit point: snap-through): an equilibrium may still
     * exist off that path; a direct cold solve may find it */
    memcpy(both, d->message, TR_MSGLEN);
    d->lam_act = d->lam_load = 1.0;
    st3 = tr_solve_init(m, d, NULL, NULL);
    if (st3 == TR_OK) st3 = tr_newton_run(m, d, d->opt.max_iter, TR_STALL_ITERS, TR_STALL_RATIO);
    if (st3 != TR_OK) {
        if (d->stop) return d->stop;
        tr_set_message(d, "%s; a direct solve did not converge either", both);
        return TR_ECONTINUATION;
    }
    tr_set_message(d,
                   "converged by a direct solve, but load continuation from the "
                   "unloaded robot stalled (%s): this equilibrium may not be the "
                   "one reached by loading the robot (a limit point / "
                   "snap-through lies on the path)",
                   second);
    return TR_OFFPATH; /* to be confirmed (solve_confirm) */
}

/* An equilibrium found off the load path (TR_OFFPATH: continuation's last resort) is the
 * answer only if a cold solve with another shooting formulation reaches it too: the
 * driver runs that solve itself, tr_confirm.c sets it up and judges it.  A workspace
 * that confirms another's does not confirm in turn. */
static int solve_confirm(const tr_model *m, tr_data *d, int status)
{
    tr_confirm c;
    int st;
    if (status != TR_OFFPATH || d->is_confirm) return status;
    st = tr_confirm_begin(m, d, &c);
    if (st != TR_CONTINUE) return st;
    st = tr_solve(d->confirm_m, d->confirm_d, NULL, NULL);
    return tr_confirm_judge(m, d, &c, st);
}

static double shared_stiffness(const tr_model *m);

static int solve_condition(const tr_model *m, tr_data *d, int status, const double *jac)
{
    /* A cold solve returns a finite-difference Jacobian at (or next to) the solution: it
     * makes the condition estimate meaningful and warm starts from it Newton-fast.  The
     * last Newton Jacobian (finite differences, then Broyden-updated along the final
     * steps) serves when it was differenced at the same step count within TR_J_MOVE of the
     * solution and its condition is at most TR_COND_TRUST; otherwise a fresh one is taken
     * at the solution.  Warm solves keep the updated one (it came from a nearby fresh one). */
    /* a converged solve's final Jacobian, polish and condition estimate are its outputs,
     * paid beyond the budget (bounded: one Jacobian, TR_POLISH_STEPS + 2 LUs); an
     * interrupt still stops them */
    const int finishing = d->finishing;
    double cond = NAN;
    if (status >= 0) d->finishing = 1;
    if (status >= 0 && !jac && !d->J_fresh && d->k > 0) {
        if (d->have_J && d->njev > 0 && d->steps_J == d->steps &&
            tr_rel_move(d->x, d->x_J, d->k) <= TR_J_MOVE)
            cond = tr_jacobian_cond(d);
        if (!(cond <= TR_COND_TRUST) && !d->stop) {
            cond = NAN;
            if (tr_fd_jacobian(m, d) != TR_OK) d->have_J = 0;
        }
    }
    /* (the polish moves the point, not the Jacobian: its condition stays) */
    if (status >= 0 && d->have_J) tr_polish(m, d);
    if (!d->stop) d->jacobian_cond = !d->have_J ? NAN : isnan(cond) ? tr_jacobian_cond(d) : cond;
    d->finishing = finishing;
    if (d->stop) return d->stop;
    if (status >= 0 && d->shared_mode) {
        /* the near-null direction is the shared tension level, solved on its own */
        const size_t len = strlen(d->branch_note);
        snprintf(d->branch_note + len, sizeof d->branch_note - len,
                 "%sthe tension level the stiff tendons share (r^2 EA/EI up to %.3g) was solved "
                 "along its own direction (Jacobian condition %.3g)",
                 len ? "; " : "", shared_stiffness(m), d->jacobian_cond);
        return status;
    }
    if (status >= 0 && d->jacobian_cond > TR_COND_SINGULAR) {
        tr_set_message(d,
                       "converged, but the Jacobian is nearly singular (condition %.3g): the "
                       "tendon tensions are poorly determined; if opposing inextensible tendons "
                       "act on an inextensible backbone the problem is statically indeterminate: "
                       "give the tendons a finite EA or the backbone an extension stiffness",
                       d->jacobian_cond);
        return TR_ILLCONDITIONED;
    }
    if (status < 0 && d->jacobian_cond > TR_COND_SINGULAR && m->ndisp >= 2) {
        char first[TR_MSGLEN];
        memcpy(first, d->message, TR_MSGLEN);
        tr_set_message(d,
                       "%s; the Jacobian is nearly singular (condition %.3g): the tendon "
                       "tensions may be statically indeterminate (give the tendons a finite EA "
                       "or the backbone an extension stiffness)",
                       first, d->jacobian_cond);
    }
    return status;
}

/* The largest r^2 EA / EI of a displacement-controlled tendon with a finite EA that shares
 * a tension level with others (0 if none). */
static double shared_stiffness(const tr_model *m)
{
    double stiff = 0.0;
    int i;
    if (m->ndisp < 2) return 0.0;
    for (i = 0; i < m->nt; i++) {
        const tr_tendon *t = m->tendon + i;
        const double ratio = t->b * t->b * t->EA / m->EI;
        if (t->control == TR_DISPLACEMENT && isfinite(t->EA) && ratio > stiff &&
            tr_shared_weight(m, i) != 0.0)
            stiff = ratio;
    }
    return stiff;
}

/* Solve with the tendons' EA scaled down to r^2 EA/EI = TR_SOFT_RATIO (cold, then by
 * continuation), then scale it back up in steps of at most TR_STIFFEN_STEP, each a Newton
 * run from the last solution with a secant predictor in log EA, halving a step that
 * fails; 0 when the scene is solved at its own EA. */
static int soften_and_stiffen(const tr_model *m, tr_data *d)
{
    const int k = d->k;
    double s = TR_SOFT_RATIO / shared_stiffness(m), s_prev = 0.0, fac = TR_STIFFEN_STEP;
    int st, i, have_prev = 0;
    if (!(s < 1.0)) return TR_ECONTINUATION;
    d->lam_act = d->lam_load = d->lam_hom = 1.0; /* a stalled continuation left them lower */
    d->ea_scale = s;
    st = tr_solve_init(m, d, NULL, NULL);
    if (st == TR_OK) st = tr_newton_run(m, d, d->opt.max_iter, TR_STALL_ITERS, TR_STALL_RATIO);
    if (st != TR_OK && st != TR_EMAXFEV && !d->stop && d->opt.continuation &&
        d->opt.max_continuation > 0)
        st = tr_continuation(m, d);
    if (st != TR_OK) {
        d->ea_scale = 1.0;
        if (!d->stop && st != TR_EMAXFEV)
            tr_set_message(d,
                           "the scene with tendons softened to r^2 EA/EI = %g did not solve "
                           "either",
                           TR_SOFT_RATIO);
        return st;
    }
    while (s < 1.0) {
        const double s_new = s * fac < 1.0 ? s * fac : 1.0;
        memcpy(d->xs, d->x, (size_t)k * sizeof(double));
        memcpy(d->fs, d->f, (size_t)k * sizeof(double));
        if (have_prev)
            for (i = 0; i < k; i++)
                d->x[i] += (d->x[i] - d->xp[i]) * log(s_new / s) / log(s / s_prev);
        d->ea_scale = s_new;
        d->have_J = 0;
        st = tr_residual(m, d, d->x, d->f);
        d->fnorm = tru_maxnorm(d->f, k);
        if (st == TR_OK) st = tr_newton_run(m, d, TR_SHARED_ITER, TR_STALL_ITERS, TR_STALL_RATIO);
        if (st == TR_EMAXFEV || d->stop) break;
        if (st == TR_OK) {
            memcpy(d->xp, d->xs, (size_t)k * sizeof(double));
            s_prev = s;
            s = s_new;
            have_prev = 1;
            fac = fac * fac < TR_STIFFEN_STEP ? fac * fac : TR_STIFFEN_STEP;
            continue;
        }
        memcpy(d->x, d->xs, (size_t)k * sizeof(double));
        memcpy(d->f, d->fs, (size_t)k * sizeof(double));
        d->ea_scale = s;
        fac = sqrt(fac);
        if (fac < TR_STIFFEN_MIN) {
            char last[TR_MSGLEN];
            memcpy(last, d->message, TR_MSGLEN);
            tr_set_message(d,
                           "stiffening the tendons from r^2 EA/EI = %g stalled at %.3g of their "
                           "EA (r^2 EA/EI = %.3g): %s",
                           TR_SOFT_RATIO, s, s * shared_stiffness(m), last);
            st = TR_ECONTINUATION;
            break;
        }
    }
    d->ea_scale = 1.0;
    if (st == TR_OK) {
        /* the same equation at scale 1: its residual, for the stages after */
        st = tr_residual(m, d, d->x, d->f);
        d->fnorm = tru_maxnorm(d->f, k);
        if (st == TR_OK && tr_solve_test(m, d) != TR_OK)
            st = tr_newton_run(m, d, TR_SHARED_ITER, TR_STALL_ITERS, TR_STALL_RATIO);
    }
    return st;
}

/* Stiff tendons sharing a tension level: that level is fixed only by their stretch and
 * second-order shape terms, a near-null direction of the Jacobian (its column ~ EI/(r^2
 * EA) of the others, lost in the rounding of the per-column differences).  A solve that
 * failed retries with that direction differenced on its own and steps that may grow
 * with the tension (d->shared_mode): from the guess or cold, by continuation, then from
 * softer tendons. */
/* A model with channel friction that failed at the automatic step count is solved again by
 * continuation at TR_FRIC_REFINE times the steps, at most twice: a tendon sliding out has
 * its tension grow like 1 / (s* - s) toward the tip as its path nears the centre of
 * curvature, which coarse steps do not resolve, and the discrete equations then have no
 * solution near the true one (measured: a Cosserat rod at r kappa(L) = 0.99 fails from
 * any start at 8-32 rk8 steps and converges at 48). */
static int solve_finer(const tr_model *m, tr_data *d, int status)
{
    char first[TR_MSGLEN], second[TR_MSGLEN];
    int round, st = status;
    if (!(status < 0 && status != TR_EMAXFEV && !d->stop && m->nfric && d->opt.steps == 0 &&
          d->opt.integrator != TR_ADAPTIVE && d->opt.continuation && d->opt.max_continuation > 0))
        return status;
    memcpy(first, d->message, TR_MSGLEN);
    for (round = 0; round < 2 && d->steps * TR_FRIC_REFINE <= TR_STEP_CAP; round++) {
        /* each attempt has max_continuation stages of its own; all are counted */
        const int spent = d->cont_steps;
        d->steps *= TR_FRIC_REFINE;
        d->have_J = 0;
        d->cont_steps = 0;
        st = tr_continuation(m, d);
        d->cont_steps += spent;
        if (st == TR_OK) {
            d->via_path = 1;
            return TR_OK;
        }
        if (st == TR_EMAXFEV || d->stop) break;
    }
    if (d->stop) return d->stop;
    if (st == status) return status;
    memcpy(second, d->message, TR_MSGLEN);
    tr_set_message(d, "%s; then at %d steps: %s", first, d->steps, second);
    return st;
}

static int solve_shared(const tr_model *m, tr_data *d, int status, const double *guess)
{
    char first[TR_MSGLEN];
    int st;
    if (!(status < 0 && status != TR_EMAXFEV && !d->stop && !d->shared_mode &&
          shared_stiffness(m) > TR_STIFF_HINT))
        return status;
    memcpy(first, d->message, TR_MSGLEN);
    d->shared_mode = 1;
    d->lam_act = d->lam_load = d->lam_hom = 1.0;
    st = tr_solve_init(m, d, guess, NULL);
    if (st == TR_OK) st = tr_newton_run(m, d, TR_SHARED_ITER, TR_STALL_ITERS, TR_STALL_RATIO);
    if (st != TR_OK && st != TR_EMAXFEV && !d->stop && d->opt.continuation &&
        d->opt.max_continuation > 0)
        st = tr_continuation(m, d);
    if (st != TR_OK && st != TR_EMAXFEV && !d->stop) st = soften_and_stiffen(m, d);
    if (st == TR_OK) return TR_OK;
    if (d->stop) return d->stop;
    {
        char second[TR_MSGLEN];
        memcpy(second, d->message, TR_MSGLEN);
        tr_set_message(d,
                       "%s; with the shared tension level of the stiff tendons differenced on "
                       "its own: %s",
                       first, second);
    }
    return st;
}

/* A converged solution of stiff tendons: do its residuals fix the shared tension level? */
static int shared_resolved(const tr_model *m, tr_data *d, int status)
{
    double dtau, tmax = 0.0;
    int i;
    if (!(status >= 0 && !d->stop && shared_stiffness(m) > TR_STIFF_HINT)) return status;
    dtau = tr_shared_resolution(m, d);
    for (i = 0; i < m->nt; i++)
        if (d->tau[i] > tmax) tmax = d->tau[i];
    if (dtau > TR_SHARED_RESOLVE * tmax && d->fnorm > TR_RESIDUAL_NOISE) {
        /* the level is fixed only as well as the residual: iterate it down to its rounding
         * level before judging (a refused answer's unknowns are what is left) */
        const double tol = d->tol_override;
        const int shared = d->shared_mode;
        d->tol_override = TR_RESIDUAL_NOISE;
        d->shared_mode = 1;
        tr_newton_run(m, d, TR_SHARED_ITER, TR_STALL_ITERS, TR_STALL_RATIO);
        d->tol_override = tol;
        d->shared_mode = shared;
        if (d->stop) return d->stop;
        dtau = tr_shared_resolution(m, d);
        tmax = 0.0;
    }
    for (i = 0; i < m->nt; i++)
        if (d->tau[i] > tmax) tmax = d->tau[i];
    if (!(dtau > TR_SHARED_RESOLVE * tmax)) return status;
    tr_set_message(d,
                   "converged, but the tension level the stiff tendons share (r^2 EA/EI up to "
                   "%.3g) is fixed by the residuals only to +-%.3g N of %.4g N (the stretch it "
                   "causes is below what the residual %.3g resolves): the tensions are not "
                   "determined in double precision at this stiffness; give the tendons a finite "
                   "EA at most ~%.3g of this one",
                   shared_stiffness(m), dtau, tmax, d->fnorm, TR_SHARED_RESOLVE * tmax / dtau);
    return TR_EINDETERMINATE;
}

static void diagnose_stiff(const tr_model *m, tr_data *d, int status)
{
    const double stiff = shared_stiffness(m);
    char first[TR_MSGLEN];
    if (!(status < 0 && status != TR_EMAXFEV && status != TR_EINDETERMINATE)) return;
    if (!(stiff > TR_STIFF_HINT)) return;
    memcpy(first, d->message, TR_MSGLEN);
    tr_set_message(d,
                   "nearly inextensible tendons (r^2 EA/EI up to %.3g: the tension "
                   "level they share is set only by their stretch, poorly resolved by "
                   "Newton; try a softer EA, or a guess solved with softer tendons): %s",
                   stiff, first);
}

/* A tendon of offset r pulling with tension tau bends the backbone at a moment-free end
 * to curvature tau r / EI; at tau = EI / r^2 that is 1/r, where the tendon's path-length
 * rate 1 - kappa r vanishes and the tendon would pass the centre of curvature.  A failed
 * solve whose last iterate loads a tendon with more than TR_CURVATURE_HINT of that says
 * so (load paths that need more stall at 0.96-0.99). */
static void diagnose(const tr_model *m, tr_data *d, int status)
{
    char first[TR_MSGLEN], named[TR_MSGLEN];
    double rate;
    int i;
    /* the closest approach of a tendon to the centre of curvature where a load path
     * stalled, or on the last iterate */
    d->lam_act = d->lam_load = 1.0;
    rate = tr_watch_curvature(m, d, d->x, 1);
    if (tr_watch_message(m, d, named, sizeof named)) {
        memcpy(first, d->message, TR_MSGLEN);
        tr_set_message(d, "%s; %s", named, first);
        return;
    }
    /* an iterate that can be walked shows where the tendons run: no tendon near the centre
     * of curvature (balanced tendon sets carry any tension without bending the robot) */
    if (isfinite(rate)) return;
    tr_set_tensions(m, d, d->x);
    for (i = 0; i < m->nt; i++) {
        const tr_tendon *t = m->tendon + i;
        const double tau = d->tau[i], rb = t->b, re = t->b + t->a * t->t;
        const double r = rb > re ? rb : re;
        double ratio;
        if (!(tau > 0.0) || !(r > 0.0)) continue;
        ratio = tau * r * r / m->EI;
        if (!(ratio >= TR_CURVATURE_HINT && isfinite(ratio))) continue;
        memcpy(first, d->message, TR_MSGLEN);
        tr_set_message(d,
                       "the last iterate loads tendon %d with %.4g N = %.2f EI/r^2 (EI/r^2 = "
                       "%.4g N): near that tension the backbone curvature tau r/EI at a "
                       "moment-free end approaches 1/r, where the tendon would pass the centre "
                       "of curvature, so no valid equilibrium lies past that point on this load "
                       "path (reduce the load or the actuation, or route the tendon closer to "
                       "the centre line); %s",
                       i, tau, ratio, m->EI / (r * r), first);
        return;
    }
}

/* The diagnosis above for a failed solve, also one whose work budget ran out (its walk of
 * the last iterate is one more integration, as the final outputs are); not after an
 * interrupt. */
static void diagnose_curvature(const tr_model *m, tr_data *d, int status)
{
    const int stop = d->stop, finishing = d->finishing;
    if (TR_SUCCEEDED(status) || status == TR_ENOEQUILIBRIUM) return;
    if (stop && stop != TR_EBUDGET) return;
    d->stop = TR_OK;
    d->finishing = 1;
    diagnose(m, d, status);
    if (!d->stop) d->stop = stop;
    d->finishing = finishing;
}

/* A model compiled for other loads (a Problem, a sweep) keeps its shooting segments; when
 * a failed solve's loads would have chosen more, say so. */
static void diagnose_segments(const tr_model *m, tr_data *d, int status)
{
    char first[TR_MSGLEN];
    double g;
    int M;
    if (TR_SUCCEEDED(status) || d->stop || !d->opt.auto_shooting) return;
    g = tr_shooting_growth(m);
    M = tr_auto_segments(g);
    if (M <= m->nshoot) return;
    memcpy(first, d->message, TR_MSGLEN);
    tr_set_message(d,
                   "these tensile loads grow the shooting sensitivities like exp(%.3g) and "
                   "would be compiled with %d shooting segments, but this problem was compiled "
                   "with %d for other loads: solve the scene with tr.solve, or build the "
                   "Problem from a scene with these loads; %s",
                   g, M, m->nshoot, first);
}

/* A converged solve with channel friction whose frictionless twin is unstable
 * (tr_stability.c): a success with that caveat, and where to look for the state the twin
 * would take. */
static int friction_held(const tr_model *m, tr_data *d, int status)
{
    char done[TR_MSGLEN];
    if (status != TR_OK || m->nfric == 0 || d->stab_twin != 0) return status;
    tr_message_converged(done, TR_MSGLEN, d->nit, d->fnorm, d->opt.tol);
    tr_set_message(d,
                   "%s; held by friction only, if at all: stability with friction is not "
                   "tested, and the frictionless twin of this state (mu = 0, the same "
                   "tensions) is unstable (margin %.4g EI/L, %d negative %s); for the state "
                   "the rod takes where friction does not hold, solve with friction = 0, or "
                   "with a small tip load across the bending plane%s",
                   done, d->stab_twin_margin, d->stab_twin_index,
                   d->stab_twin_index == 1 ? "mode" : "modes",
                   m->planar ? " and force_spatial=True (this planar formulation cannot "
                               "leave the plane)"
                             : "");
    return TR_FRICTION_HELD;
}

/* The message of a solve that the budget or an interrupt stopped. */
static void stop_message(const tr_model *m, tr_data *d)
{
    char first[TR_MSGLEN], where[96];
    const char *sep = d->message[0] ? "; last: " : "";
    memcpy(first, d->message, TR_MSGLEN);
    if (isfinite(d->fnorm))
        snprintf(where, sizeof where, "after %d iterations (scaled residual %.3g)", d->nit,
                 d->fnorm);
    else
        snprintf(where, sizeof where, "after %d iterations", d->nit);
    if (d->stop == TR_EINTERRUPTED) {
        tr_set_message(d, "interrupted by the caller %s", where);
    } else if (d->opt.max_time > 0.0 && tr_clock() - d->t_start > d->opt.max_time) {
        tr_set_message(d,
                       "the time limit ran out (max_time = %g s) %s; raise Options.max_time, "
                       "give a guess from a nearby solved scene, or approach this scene in "
                       "smaller steps (a sweep)%s%s",
                       d->opt.max_time, where, sep, first);
    } else {
        tr_set_message(d,
                       "the work budget ran out (max_work = %.3g units) "
                       "%s: the scene may have no equilibrium near the path tried; raise "
                       "Options.max_work, give a guess from a nearby solved scene, or approach "
                       "this scene in smaller steps (a sweep)%s%s",
                       d->opt.max_work, where, sep, first);
    }
}

static int solve_record(const tr_model *m, tr_data *d, int status)
{
    int rs;
    d->residual_norm = d->fnorm;
    d->lam_act = d->lam_load = 1.0;
    if (status == TR_EINTERRUPTED) return status;
    /* the states of the last iterate are recorded even when the budget ran out */
    if (d->stop == TR_EBUDGET) d->stop = TR_OK;
    d->finishing = 1;
    rs = tr_tip_state(m, d);
    if (!d->lazy) {
        /* the node arrays (NaN where the recording fails: nothing stale) */
        const int rr = tr_record(m, d);
        if (rs == TR_OK) rs = rr;
    }
    d->finishing = 0;
    if (rs == TR_EINTERRUPTED) return rs;
    if (rs != TR_OK && status >= 0) {
        status = rs;
        tr_set_message(d, "the recording pass failed: %s", tr_strerror(rs));
    }
    /* converged above tol: at the residual's round-off floor (tr_solve_test); a step
     * count the doubling could not verify then says so after it */
    if ((status == TR_OK || status == TR_TRUNCATION) && d->residual_norm > d->opt.tol) {
        char trunc[TR_MSGLEN];
        memcpy(trunc, d->message, TR_MSGLEN);
        tr_message_floor(d->message, TR_MSGLEN, d->nit, d->residual_norm, d->opt.tol,
                         tr_roundoff_floor(m, d));
        if (status == TR_TRUNCATION && trunc[0]) {
            const size_t len = strlen(d->message);
            snprintf(d->message + len, TR_MSGLEN - len, "; %s", trunc);
        }
        status = TR_ROUNDOFF;
        if (d->branch_note[0]) {
            const size_t len = strlen(d->message);
            snprintf(d->message + len, TR_MSGLEN - len, "; %s", d->branch_note);
        }
    } else if (status == TR_OK) {
        tr_message_converged(d->message, TR_MSGLEN, d->nit, d->residual_norm, d->opt.tol);
        if (d->branch_note[0]) {
            const size_t len = strlen(d->message);
            snprintf(d->message + len, TR_MSGLEN - len, "; %s", d->branch_note);
        }
    } else if (status == TR_TRUNCATION && d->message[0] == '\0')
        tr_set_message(d, "%s", tr_strerror(status));
    if (TR_SUCCEEDED(status)) {
        /* kept for the next warm solve */
        memcpy(d->x_last, d->x, (size_t)d->k * sizeof(double));
        memcpy(d->J_last, d->J, (size_t)d->k * d->k * sizeof(double));
        d->steps_last = d->steps;
        d->have_last = d->have_J;
        memcpy(d->x_ver_last, d->x_ver, (size_t)d->k * sizeof(double));
        d->est_ver_last = d->est_ver;
        d->steps_ver_last = d->steps_ver;
        d->have_ver_last = d->have_ver;
        memcpy(d->val_ver_last, d->val_ver, (size_t)m->nt * sizeof(double));
        d->have_val_ver_last = d->have_val_ver;
        tr_branch_keep(m, d);
    }
    return status;
}

/* The verification record a solve starts with: the last successful solve's (warm), the
 * guess's (v), or none. */
static void begin_verified(tr_data *d, const tr_verified *v, int from_last)
{
    const size_t kb = (size_t)d->k * sizeof(double), nb = (size_t)d->vm->nt * sizeof(double);
    d->have_ver = d->ver_carried = d->have_val_ver = 0;
    if (from_last && d->have_ver_last) {
        memcpy(d->x_ver, d->x_ver_last, kb);
        d->est_ver = d->est_ver_last;
        d->steps_ver = d->steps_ver_last;
        d->have_ver = 1;
        memcpy(d->val_ver, d->val_ver_last, nb);
        d->have_val_ver = d->have_val_ver_last;
    } else if (!from_last && v && v->x && v->steps > 0) {
        memcpy(d->x_ver, v->x, kb);
        d->est_ver = v->estimate;
        d->steps_ver = v->steps;
        d->have_ver = 1;
        if (v->values) {
            memcpy(d->val_ver, v->values, nb);
            d->have_val_ver = 1;
        }
    }
}

/* A converged state whose truncation estimate stayed above tol at the step cap is walked
 * for a taut tendon at or past the centre of curvature (its path-length rate along its
 * unstressed direction below TR_WATCH_PAST: the equations are singular there, past it the
 * tendon's path runs backwards): such a state is beyond the model, not an answer. */
static int past_centre(const tr_model *m, tr_data *d, int status)
{
    char named[TR_MSGLEN], first[TR_MSGLEN];
    if (status != TR_TRUNCATION || m->nt == 0) return status;
    if (!tr_watch_named(m, d, d->x, "at the converged state", named, sizeof named) ||
        !(d->watch_rate < TR_WATCH_PAST))
        return status;
    memcpy(first, d->message, TR_MSGLEN);
    tr_set_message(d, "no answer within the model: %s; (%s)", named, first);
    return TR_ENOEQUILIBRIUM;
}

/* A cold direct try whose answer the verdict did not call stable (TR_DIRECT_DOUBT, from
 * tr_branch): the load path from the unloaded robot instead, through the same stages as a
 * forced continuation (continuation, confirmation, finer steps, shared level, branch). */
static int solve_doubted(const tr_model *m, tr_data *d, int status, const double *guess)
{
    int forced;
    if (status != TR_DIRECT_DOUBT) return status;
    status = direct_fallback(m, d, &forced,
                             d->stable == 0 ? "; direct Newton reached an unstable equilibrium"
                                            : "; direct Newton reached an equilibrium whose "
                                              "stability was not judged");
    status = solve_continuation(m, d, status, forced);
    status = solve_confirm(m, d, status);
    status = solve_finer(m, d, status);
    status = solve_shared(m, d, status, guess);
    return tr_branch(m, d, status, 1);
}

static int solve(const tr_model *m, tr_data *d, const double *guess, const double *jac,
                 const tr_verified *v, int from_last)
{
    int status, forced;
    status = solve_begin(m, d, v);
    if (status != TR_OK) return d->status = status;
    begin_verified(d, v, from_last);
    status = solve_direct(m, d, guess, jac, from_last, &forced);
    if (status == TR_EINVAL) return d->status = status;
    status = solve_continuation(m, d, status, forced);
    status = solve_confirm(m, d, status);
    status = solve_finer(m, d, status);
    status = solve_shared(m, d, status, guess);
    status = tr_branch(m, d, status, !guess && !from_last);
    status = solve_doubted(m, d, status, guess);
    if (status >= 0 && d->opt.steps == 0 && d->opt.integrator != TR_ADAPTIVE &&
        !tr_verify_carried(m, d)) {
        const int vs = tr_verify_steps(m, d);
        if (vs != TR_OK) status = vs;
    }
    status = tr_verify_fixed(m, d, status);
    status = past_centre(m, d, status);
    status = solve_condition(m, d, status, from_last ? d->J_last : jac);
    status = shared_resolved(m, d, status);
    status = friction_held(m, d, status);
    if (d->stop) {
        status = d->stop;
        stop_message(m, d);
    }
    diagnose_stiff(m, d, status);
    diagnose_curvature(m, d, status);
    diagnose_segments(m, d, status);
    status = solve_record(m, d, status);
    d->nfev += d->nfev_confirm;
    return d->status = status;
}

int tr_solve(const tr_model *m_, tr_data *d, const double *guess, const double *jac)
{
    const tr_model *m = TR_IN(m_, d);
    return solve(m, d, guess, jac, NULL, 0);
}

int tr_solve_from(const tr_model *m_, tr_data *d, const double *guess, const double *jac,
                  const tr_verified *v)
{
    const tr_model *m = TR_IN(m_, d);
    return solve(m, d, guess, jac, v, 0);
}

int tr_solve_warm(const tr_model *m_, tr_data *d)
{
    const tr_model *m = TR_IN(m_, d);
    return solve(m, d, NULL, NULL, NULL, d->have_last);
}

void tr_forget(tr_data *d)
{
    d->have_last = 0;
    d->have_ver_last = 0;
}
