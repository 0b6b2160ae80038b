/*
 * tr_branch.c -- the stable branch: the stability stage of a converged solve.
 *
 * Verdict: a cold solve is judged by tr_stability_quick.  A warm solve keeps the verdict
 * of the last judged solve of its workspace while it stays close to it: the shooting
 * Jacobian's determinant has kept its sign (an odd number of eigenvalues crossing zero
 * flips it) and the scaled change since -- of the actuation values and loads, plus that
 * of the unknowns times 1 + the load-induced stiffness scale -- is below TR_CARRY of
 * that verdict's distance from zero (an even number crossing together, as in the
 * buckling of a round column, leaves the sign alone but needs a change of that size);
 * else it is judged afresh.
 *
 * Unless Options.accept_unstable:
 *   1. a warm answer whose tip lies more than TR_CONT_TIP_JUMP L from its guess's, or an
 *      unstable one, is redone by continuation from the guess (lam_hom: the residual
 *      minus (1 - lam_hom) times the guess's, from 0 to 1), which reaches the equilibrium
 *      continuously connected to the guess;
 *   2. an unstable answer not reached along the load path follows the load path from the
 *      unloaded robot (tr_continuation);
 *   3. where that path ends unstable too (a symmetric bifurcation lies on it), a small tip
 *      imperfection (TR_IMPERFECTION EI/L^2 along the tip's body x, y and the two
 *      diagonals, then a moment TR_IMPERFECTION EI/L about its tangent; in-plane only for
 *      a planar model) breaks the symmetry along the load path and is then removed along
 *      the branch (lam_imp);
 *   4. where none of these reaches a stable equilibrium, the first unstable one is handed
 *      back with TR_UNSTABLE, not a success, and a message that says what was tried.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "tendonrod.h"
#include "tr_internal.h"
#include "tru_math.h"

/* Value n of the list: stored in v (old NULL), or its change from old added up. */
static void value(double x, double *v, const double *old, int *n, double *change)
{
    if (old)
        *change += fabs(x - old[*n]);
    else
        v[*n] = x;
    (*n)++;
}

/* The scaled values the verdict depends on besides the unknowns: actuation (q / r for
 * displacements, tau L^2 / EI for tensions), breakpoints (s / L, weighted by 1 + their
 * loads) and their loads (F L^2 / EI, M L / EI), the distributed force (f L^3 / EI):
 * into v (old NULL), or the sum of their absolute changes from old. */
static double values_of(const tr_model *m, double *v, const double *old)
{
    double change = 0.0;
    int i, b, c, n = 0;
    for (i = 0; i < m->nt; i++) {
        const tr_tendon *t = m->tendon + i;
        const double r = fmax(fabs(t->b), fabs(t->b + t->a * t->t));
        value(t->control == TR_DISPLACEMENT ? t->value / (r > 0.0 ? r : m->L) : t->value / m->F_s,
              v, old, &n, &change);
    }
    for (b = 0; b <= m->nseg; b++) {
        /* where the loads act: a breakpoint's arc length, weighted by its loads */
        const double w =
            1.0 + tru_norm3(m->bpF + 3 * b) / m->F_s + tru_norm3(m->bpM + 3 * b) / m->M_s;
        value(w * m->bp[b] / m->L, v, old, &n, &change);
        for (c = 0; c < 3; c++) {
            value(m->bpF[3 * b + c] / m->F_s, v, old, &n, &change);
            value(m->bpM[3 * b + c] / m->M_s, v, old, &n, &change);
        }
    }
    for (c = 0; c < 3; c++) value(m->dist[c] * m->L / m->F_s, v, old, &n, &change);
    return change;
}

void tr_branch_keep(const tr_model *m_, tr_data *d)
{
    const tr_model *m = TR_IN(m_, d);
    /* a kept verdict leaves the base it was kept from: later solves compare with the
     * solve that judged it, so that small changes do not add up unseen */
    if (d->stab_kept) return;
    d->carry_valid = 0;
    if (d->stable < 0 || !(d->stab_gap > 0.0) || !d->have_J || tr_lu_factor(d) != 0) return;
    d->carry_valid = 1;
    d->carry_stable = d->stable;
    d->carry_index = d->stab_index;
    d->carry_det = d->lu_sign;
    d->carry_gap = d->stab_gap;
    d->carry_margin = d->stability;
    memcpy(d->carry_x, d->x, (size_t)d->k * sizeof(double));
    values_of(m, d->carry_val, NULL);
    snprintf(d->carry_reason, sizeof d->carry_reason, "%s", d->stab_reason);
}

/* The verdict of the current unknowns: kept from the last successful solve when close to
 * it (may_carry), else judged afresh. */
static void judge(const tr_model *m, tr_data *d, int may_carry)
{
    d->stab_kept = 0;
    if (may_carry && d->carry_valid && d->have_J && tr_lu_factor(d) == 0 &&
        d->lu_sign == d->carry_det) {
        /* the loads enter the second variation linearly (their change, scaled), the
         * configuration through every term (the change of the unknowns, times 1 + the
         * stiffness scale) */
        const double loads = values_of(m, NULL, d->carry_val);
        double config = 0.0, change, scaled;
        int i;
        tr_set_tensions(m, d, d->x);
        for (i = 0; i < d->k; i++) config += fabs(d->x[i] - d->carry_x[i]) / d->k;
        change = loads + config;
        scaled = loads + config * (1.0 + tr_stiffness_scale(m, d));
        if (scaled < TR_CARRY * d->carry_gap) {
            d->stable = d->carry_stable;
            d->stab_index = d->carry_index;
            d->stab_gap = d->carry_gap - scaled;
            d->stability = NAN;
            d->stab_kept = 1;
            snprintf(d->stab_reason, sizeof d->stab_reason,
                     "%.150s (kept from the solve that judged it: a scaled change of %.2g since)",
                     d->carry_reason, change);
            return;
        }
    }
    tr_stability_quick(m, d);
}

/* The tip position and rotation at d->x: from the last evaluation when it was there. */
static void tip_pose(const tr_model *m, tr_data *d, double p[3], double R[9])
{
    double n[3], mo[3];
    if (!tr_holds_end_state(d, d->x) && tr_residual(m, d, d->x, d->ft) != TR_OK) {
        p[0] = p[1] = p[2] = NAN;
        return;
    }
    tr_state_world(m, d->y, p, R, n, mo);
}

/* Back at the full actuation and loads, the residual at d->x refreshed (after a
 * continuation, which may have stopped part-way); each continuation gets the full
 * max_continuation stages, d->cont_steps their total. */
static int settle(const tr_model *m, tr_data *d, int status)
{
    d->lam_act = d->lam_load = d->lam_hom = 1.0;
    d->cont_total += d->cont_steps;
    d->cont_steps = 0;
    if (status == TR_OK) {
        status = tr_residual(m, d, d->x, d->f);
        d->fnorm = tru_maxnorm(d->f, d->k);
        if (status == TR_OK && !(d->fnorm <= d->opt.tol)) status = TR_ENOPROGRESS;
    }
    return status;
}

/* Continuation from the guess of this solve (lam_hom from 0 to 1). */
static int from_guess(const tr_model *m, tr_data *d)
{
    const int saved = d->jac_method;
    int status;
    memcpy(d->x, d->x_guess, (size_t)d->k * sizeof(double));
    d->lam_hom = 0.0;
    d->have_J = 0;
    d->jac_method = TR_JAC_NEWTON;
    status = tr_residual(m, d, d->x, d->f);
    d->fnorm = tru_maxnorm(d->f, d->k);
    if (status == TR_OK) status = tr_ramp(m, d, &d->lam_hom, "continuation from the guess", 1.0);
    d->lam_hom = 1.0;
    d->jac_method = saved;
    return settle(m, d, status);
}

static const double imperfection_dir[TR_N_IMPERFECTIONS][3] = {
    {1.0, 0.0, 0.0},
    {0.0, 1.0, 0.0},
    {0.70710678118654752, 0.70710678118654752, 0.0},
    {0.70710678118654752, -0.70710678118654752, 0.0},
    {0.0, 0.0, 1.0}};

/* Load continuation with imperfection `which` at the tip (R: the tip rotation of the
 * unstable answer), then its removal.  *what: a description for the message. */
static int imperfect(const tr_model *m, tr_data *d, int which, const double *R, char *what,
                     size_t len)
{
    const int force = which < TR_N_IMPERFECTIONS - 1;
    const double size = TR_IMPERFECTION * (force ? m->F_s : m->M_s);
    const int saved = d->jac_method;
    double u[3];
    int c, status;
    d->probe_bp = m->nseg;
    for (c = 0; c < 6; c++) d->probe[c] = 0.0;
    tru_matvec3(u, R, imperfection_dir[which]);
    for (c = 0; c < 3; c++) d->probe[(force ? 0 : 3) + c] = size * u[c];
    snprintf(what, len, "a tip %s of %.3g %s along the world direction (%.3f, %.3f, %.3f)",
             force ? "force" : "moment", size, force ? "N" : "N m", u[0], u[1], u[2]);
    d->lam_imp = 0.0;
    status = tr_continuation(m, d);
    if (status == TR_OK) {
        d->cont_total += d->cont_steps;
        d->cont_steps = 0;
        d->jac_method = TR_JAC_NEWTON;
        status = tr_ramp(m, d, &d->lam_imp, "removal of the symmetry-breaking imperfection", 1.0);
        d->jac_method = saved;
    }
    d->probe_bp = -1;
    d->lam_imp = 0.0;
    return settle(m, d, status);
}

/* What the alternatives were sought for, and what was tried. */
typedef struct {
    char what[160];        /* the first answer, in words */
    char tried[TR_MSGLEN]; /* "; ..." per attempt that did not reach a stable answer */
    const char *how;       /* "direct" or "warm" */
    double jump;           /* distance of the first answer's tip from the guess's [L] */
} alt_ctx;

static void tried(alt_ctx *a, const char *fmt, const char *detail)
{
    const size_t l = strlen(a->tried);
    snprintf(a->tried + l, sizeof a->tried - l, fmt, detail);
}

/* From the guess: to the same answer or a stable one (where the answer was unstable,
 * along stable stages only).  1: a stable answer; 2: the first, stable answer kept as
 * data (it jumped and nothing connects it to the guess); 0: neither. */
static int via_guess(const tr_model *m, tr_data *d, alt_ctx *a)
{
    int st;
    d->ramp_stable = d->stable == 0;
    st = from_guess(m, d);
    d->ramp_stable = 1;
    if (st == TR_OK) {
        judge(m, d, 0);
        if (d->stable != 0) {
            snprintf(d->branch_note, sizeof d->branch_note,
                     "the warm solve reached %s; continuation from the guess reached this one",
                     a->what);
            return 1;
        }
        tried(a, "; continuation from the guess reached an unstable one too%s", "");
    } else {
        tried(a, "; continuation from the guess failed (%.200s)", d->message);
    }
    if (a->jump > TR_CONT_TIP_JUMP && st != TR_OK && !d->stop) {
        memcpy(d->x, d->x_alt, (size_t)d->k * sizeof(double));
        judge(m, d, 0);
        if (d->stable != 0) {
            settle(m, d, TR_OK);
            tr_set_message(d,
                           "converged to %s, and continuation from the guess failed: possibly "
                           "not the equilibrium connected to the guess%s",
                           a->what, a->tried);
            return 2;
        }
    }
    return 0;
}

/* The load path from the unloaded robot, each stage stable: it stalls where the stable
 * branch it follows ends (a bifurcation or a limit point).  1: a stable answer. */
static int via_load_path(const tr_model *m, tr_data *d, alt_ctx *a)
{
    const int st = settle(m, d, tr_continuation(m, d));
    if (st != TR_OK) {
        tried(a, "; the load path from the unloaded robot stopped (%.300s)", d->message);
        return 0;
    }
    judge(m, d, 0);
    if (d->stable != 0) {
        snprintf(d->branch_note, sizeof d->branch_note,
                 "the %s solve reached %s; the load path from the unloaded robot reached this "
                 "one%s",
                 a->how, a->what, a->tried);
        return 1;
    }
    tried(a, "; the load path from the unloaded robot ends unstable too%s", "");
    return 0;
}

/* A symmetric bifurcation on the load path: break the symmetry with each imperfection
 * in turn (directions from the tip of the first answer).  1: a stable answer. */
static int via_imperfection(const tr_model *m, tr_data *d, alt_ctx *a)
{
    double p[3], R[9];
    char last[TR_MSGLEN] = "no tip pose";
    int which;
    memcpy(d->x, d->x_alt, (size_t)d->k * sizeof(double));
    tip_pose(m, d, p, R);
    for (which = 0; which < (m->planar ? 1 : TR_N_IMPERFECTIONS) && isfinite(p[0]) && !d->stop;
         which++) {
        char imp[160];
        if (imperfect(m, d, which, R, imp, sizeof imp) != TR_OK) {
            snprintf(last, sizeof last, "%s", d->message);
            continue;
        }
        judge(m, d, 0);
        snprintf(last, sizeof last, "it ends unstable");
        if (d->stable != 0) {
            snprintf(d->branch_note, sizeof d->branch_note,
                     "the %s solve reached %s, and the load path from the unloaded robot "
                     "loses stability on the way (a bifurcation); %s, applied to break the "
                     "symmetry, was then removed along this branch",
                     a->how, a->what, imp);
            return 1;
        }
    }
    tried(a, "; tip imperfections did not lead to a stable equilibrium either (the last: %.300s)",
          last);
    return 0;
}

static int branch(const tr_model *m, tr_data *d, int status, int cold)
{
    alt_ctx a;
    double p[3], R[9];
    int r;
    d->branch_note[0] = '\0';
    if (d->opt.accept_unstable || d->is_confirm || status < 0 || d->stop) return status;
    judge(m, d, !cold);
    if (cold && d->direct_try) {
        /* a cold start with large loads that direct Newton solved: its answer stands
         * only if stable (tr_solve.c then takes the load path) */
        d->direct_try = 0;
        if (d->stable != 1) return TR_DIRECT_DOUBT;
    }
    a.jump = 0.0;
    if (!cold && isfinite(d->tip_guess[0])) {
        tip_pose(m, d, p, R);
        a.jump =
            hypot(hypot(p[0] - d->tip_guess[0], p[1] - d->tip_guess[1]), p[2] - d->tip_guess[2]) /
            m->L;
    }
    if (d->stable != 0 && !(a.jump > TR_CONT_TIP_JUMP)) return status;
    if (status == TR_OFFPATH || status == TR_CONFIRMED) {
        /* found off a load path that stalled: nothing left to follow */
        if (d->stable != 0) return status;
        {
            char first[TR_MSGLEN];
            memcpy(first, d->message, TR_MSGLEN);
            tr_set_message(d, "%s; it is unstable (%s)", first, d->stab_reason);
        }
        return TR_UNSTABLE;
    }
    /* an unstable answer, or one that jumped from its guess: the alternatives, each
     * continuation stage of which must end stable */
    memcpy(d->x_alt, d->x, (size_t)d->k * sizeof(double));
    a.tried[0] = '\0';
    a.how = cold ? "direct" : "warm";
    if (d->stable == 0)
        snprintf(a.what, sizeof a.what, "an unstable equilibrium (%d negative %s)", d->stab_index,
                 d->stab_index == 1 ? "mode" : "modes");
    else
        snprintf(a.what, sizeof a.what, "an equilibrium %.2f L from the guess's tip", a.jump);
    d->ramp_stable = 1;
    r = cold ? 0 : via_guess(m, d, &a);
    if (d->stop) return d->stop;
    if (r) return r == 1 ? TR_OK : TR_OFFPATH;
    if (!(d->via_path && cold) && via_load_path(m, d, &a)) return TR_OK;
    if (d->stop) return d->stop;
    if (via_imperfection(m, d, &a)) return TR_OK;
    if (d->stop) return d->stop;
    /* none: the first answer, as data */
    memcpy(d->x, d->x_alt, (size_t)d->k * sizeof(double));
    settle(m, d, TR_OK);
    judge(m, d, 0);
    d->have_J = 0;
    tr_set_message(d,
                   "converged to %s, not a success (Options(accept_unstable=True) accepts "
                   "it)%s%s",
                   a.what, a.tried,
                   m->planar ? "; a planar solve stays in the x-z plane: where the unstable "
                               "mode leaves it (lateral buckling), Options(force_spatial=True) "
                               "and a small out-of-plane load reach the stable state"
                             : "");
    return d->stable == 0 ? TR_UNSTABLE : TR_OFFPATH;
}

int tr_branch(const tr_model *m_, tr_data *d, int status, int cold)
{
    const tr_model *m = TR_IN(m_, d);
    d->cont_total = d->cont_steps;
    d->cont_steps = 0;
    status = branch(m, d, status, cold);
    d->ramp_stable = 0;
    d->cont_steps += d->cont_total;
    return status;
}

int tr_branch_lean(const tr_model *m_, tr_data *d)
{
    const tr_model *m = TR_IN(m_, d);
    if (d->opt.accept_unstable) return 1;
    judge(m, d, 1);
    if (d->stable == 0) return 0;
    tr_branch_keep(m, d);
    return 1;
}

/* The flat record: stable, index, det sign, gap, margin, then carry_x (k), carry_val
 * (values_of's list). */
int tr_carry_len(const tr_model *m_, const tr_data *d)
{
    const tr_model *m = TR_IN(m_, d);
    return 5 + d->k + m->nt + 7 * (m->nseg + 1) + 3;
}

int tr_carry_get(const tr_model *m_, const tr_data *d, double *rec)
{
    const tr_model *m = TR_IN(m_, d);
    const int k = d->k, nv = tr_carry_len(m, d) - 5 - k;
    if (!d->carry_valid) return 0;
    rec[0] = d->carry_stable, rec[1] = d->carry_index, rec[2] = d->carry_det;
    rec[3] = d->carry_gap, rec[4] = d->carry_margin;
    memcpy(rec + 5, d->carry_x, (size_t)k * sizeof(double));
    memcpy(rec + 5 + k, d->carry_val, (size_t)nv * sizeof(double));
    return 1;
}

int tr_carry_set(const tr_model *m_, tr_data *d, const double *rec, int len, const char *reason)
{
    const tr_model *m = TR_IN(m_, d);
    const int k = d->k, nv = tr_carry_len(m, d) - 5 - k;
    int i;
    if (len != tr_carry_len(m, d) || !(rec[0] == 0.0 || rec[0] == 1.0) ||
        !(rec[2] == 1.0 || rec[2] == -1.0) || !(rec[3] > 0.0) || !(rec[1] >= 0.0))
        return -1;
    for (i = 5; i < len; i++)
        if (!isfinite(rec[i])) return -1;
    d->carry_stable = (int)rec[0], d->carry_index = (int)rec[1], d->carry_det = (int)rec[2];
    d->carry_gap = rec[3], d->carry_margin = rec[4];
    memcpy(d->carry_x, rec + 5, (size_t)k * sizeof(double));
    memcpy(d->carry_val, rec + 5 + k, (size_t)nv * sizeof(double));
    snprintf(d->carry_reason, sizeof d->carry_reason, "%s", reason);
    d->carry_valid = 1;
    return 0;
}
