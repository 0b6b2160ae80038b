/*
 * tr_stability.c -- is the solved equilibrium a strict local minimum of the total
 * potential energy?  The constrained Hessian of a discretised energy (design and
 * validation: bench/results/stability_design.md).
 *
 * The solution is recorded at the nodes of a grid (uniform plus every breakpoint); the
 * coordinates are each node's body-frame rotation perturbation (and, with Cosserat
 * elements, its position perturbation), the base clamped.  The element energies are
 * tr_element.c's; Kirchhoff elements serve Cosserat rods too (they keep a symmetry's zero
 * mode exact; shear and extension move the margin by ~EI/(GA L^2) of the load scale),
 * Cosserat elements only where the tendon constraints are dependent on the Kirchhoff
 * ones.  A displacement-controlled tendon
 * adds EA/l (g g^T) for its stretch (finite EA) or makes g^T x = 0 a constraint
 * (inextensible), g the gradient of its length.  Element Hessians come exact to
 * round-off from hyper-dual numbers (tr_hd.h); the Hessian is block tridiagonal plus
 * those bordered terms, so its inertia follows from a block LDL^T (a Sturm sequence)
 * and Haynsworth's inertia additivity, and the margin (the smallest eigenvalue in the
 * norm (1/L) int |dtheta|^2 + |dp|^2/L^2 ds, scaled by EI/L) from a bisection on the
 * inertia of H - lambda M.  The margin at half the elements gives the discretisation
 * error; a margin within it is "critical", one at round-off level "neutral".  The quick
 * test (tr_stability_quick) decides from the inertia at +-band on a coarse grid alone
 * where no eigenvalue lies near zero (its grid recorded coarsely, checked against the
 * shooting tip: tr_record_coarse), and leaves the margin to the full test; where its a
 * priori band is too wide, an a posteriori check on two grids may still decide a stable
 * solution (verdict_check).  The energy's assembly is tr_stab_energy.c's, the test at a
 * taut/slack switch tr_switch.c's.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tendonrod.h"
#include "tr_element.h"
#include "tr_hd.h"
#include "tr_internal.h"
#include "tr_stab.h"
#include "tru_math.h"

/* The margin of one level (the grid nodes of kind >= min_kind) and the count of negative
 * modes; refine: first move to the discrete equilibrium.  *coarse: 1 too few elements, 2
 * the bordered constraints are dependent on these elements (no count). */
static double level_margin(const tr_model *m, const tr_data *d, struct tr_stab_ws *w, int min_kind,
                           int refine, int *index, int *coarse)
{
    const int nb = w->nb;
    int nn = 0, j, sing, neg;
    *coarse = 0;
    for (j = 0; j < w->ngrid; j++)
        if (w->kind[j] >= min_kind) w->node[nn++] = j;
    if (tr_stab_level_setup(m, d, w, nn) < 0) {
        *coarse = 1;
        return NAN;
    }
    tr_stab_assemble(m, w, nn, nb);
    if (refine) tr_stab_discrete_equilibrium(m, w, nn, nb);
    neg = tr_btd_count(&w->h, 0.0, &sing);
    if (sing) neg = tr_btd_count(&w->h, -1e-9, &sing);
    if (sing) {
        *coarse = 2;
        return NAN;
    }
    if (index) *index = neg;
    return tr_btd_smallest(&w->h, neg > 0);
}

/* A world-fixed point moment: not conservative for spatial perturbations (reason set).
 * Channel friction is not either; it is handled by friction_twin. */
static int not_conservative(const tr_model *m, tr_data *d)
{
    int b;
    for (b = 1; b <= m->nseg; b++)
        if (m->bpM[3 * b] != 0.0 || m->bpM[3 * b + 1] != 0.0 || m->bpM[3 * b + 2] != 0.0) {
            snprintf(d->stab_reason, sizeof d->stab_reason,
                     "not tested: a point moment fixed in the world (at s = %g m) is not "
                     "conservative for spatial perturbations",
                     m->bp[b]);
            return 1;
        }
    return 0;
}

static void verdict_reset(tr_data *d)
{
    d->stab_twin = d->stab_twin_index = -1;
    d->stab_twin_margin = NAN;
    d->stable = -1;
    d->stability = NAN;
    d->stab_index = -1;
    d->stab_gap = 0.0;
    d->stab_reason[0] = '\0';
}

static void slack_side_note(const tr_model *m, tr_data *d)
{
    int i;
    for (i = 0; i < m->nt; i++)
        if (m->tendon[i].control == TR_DISPLACEMENT && d->tau[i] == 0.0 && d->beta[i] == 0.0) {
            const size_t len = strlen(d->stab_reason);
            snprintf(d->stab_reason + len, sizeof d->stab_reason - len,
                     "; tendon %d is at its taut/slack switch: the slack side is tested", i);
        }
}

/* The full test: the model's own elements, refined near zero (sets the margin). */
/* near_zero: an eigenvalue is known to lie near zero (the quick test could not decide):
 * straight to the discrete equilibrium. */
static void verdict_full(const tr_model *m, tr_data *d, int near_zero)
{
    /* Kirchhoff elements, on a Cosserat rod too (they keep a symmetry's zero mode exact,
     * which the Cosserat elements resolve only to their discretisation error; shear and
     * extension move the margin by ~(1 + stiffness scale) EI/(GA L^2)), unless the
     * bordered constraints are dependent on them (opposing inextensible tendons held by
     * the backbone's extension): then the Cosserat elements */
    int cosserat = 0, nuni = d->stab ? d->stab->nuni : TR_STAB_ELEMENTS, coarse, st;
    int refine = near_zero;
    double mf = NAN, mc = NAN, err, reduction = 0.0;
    struct tr_stab_ws *w;
    for (;;) {
        w = tr_stab_workspace(m, d, &d->stab, nuni, cosserat);
        if (!w) {
            snprintf(d->stab_reason, sizeof d->stab_reason, "not tested: out of memory");
            return;
        }
        st = tr_record_from(m, w->rec, d->x, d->steps);
        if (st != TR_OK) {
            snprintf(d->stab_reason, sizeof d->stab_reason,
                     "not tested: the solution could not be recorded (%s)", tr_strerror(st));
            return;
        }
        mf = level_margin(m, d, w, 0, refine, &d->stab_index, &coarse);
        if (!coarse && !refine && fabs(mf) < TR_STAB_CHECK * (1.0 + tr_stiffness_scale(m, d))) {
            /* close to zero: at the discrete equilibrium, and against half the elements */
            refine = 1;
            mf = level_margin(m, d, w, 0, 1, &d->stab_index, &coarse);
        }
        mc = mf;
        /* the error estimate, unless the margin is at round-off (neutral) */
        if (!coarse && refine && !(fabs(mf) <= TR_STAB_NEUTRAL))
            mc = level_margin(m, d, w, 1, 1, NULL, &coarse);
        if (!coarse) break;
        if (coarse == 2) {
            if (cosserat || m->kirchhoff) {
                snprintf(d->stab_reason, sizeof d->stab_reason,
                         "not tested: the tendon constraints are dependent");
                return;
            }
            cosserat = 1, refine = 0;
            continue;
        }
        if (2 * nuni > TR_STAB_MAX_ELEMENTS) {
            snprintf(d->stab_reason, sizeof d->stab_reason,
                     "not tested: the backbone turns too much for %d elements", nuni);
            return;
        }
        nuni *= 2;
    }
    /* the discretisation error from half the elements (second order: the finer margin is
     * off by about a third of the change) */
    if (!m->kirchhoff && !cosserat)
        reduction =
            (1.0 + tr_stiffness_scale(m, d)) * m->EI * (1.0 / m->GA + 1.0 / m->EA) / (m->L * m->L);
    err = fabs(mf - mc) / 3.0 + reduction;
    d->stability = mf;
    if (fabs(mf) <= TR_STAB_NEUTRAL) {
        d->stable = 1;
        snprintf(d->stab_reason, sizeof d->stab_reason,
                 "neutrally stable: a direction of zero stiffness (margin %.2g EI/L), such as "
                 "a symmetry of the scene",
                 mf);
    } else if (fabs(mf) <= 2.0 * err) {
        snprintf(d->stab_reason, sizeof d->stab_reason,
                 "critical within the accuracy of the test: margin %.3g EI/L, discretisation "
                 "error about %.2g",
                 mf, err);
    } else {
        d->stable = mf > 0.0;
        d->stab_gap = fabs(mf) - 2.0 * err;
        snprintf(d->stab_reason, sizeof d->stab_reason, "%s: margin %.4g EI/L (%d negative %s)",
                 mf > 0.0 ? "stable" : "unstable", mf, d->stab_index,
                 d->stab_index == 1 ? "mode" : "modes");
    }
}

/* The shooting tip's state at the solution when the solve's last evaluation left it
 * (the reference of a coarse recording), else NULL. */
static const double *shooting_tip(const tr_data *d)
{
    return tr_holds_end_state(d, d->x) ? d->y : NULL;
}

/* One eigenvalue in the quick test's band: a symmetry's zero mode?  At the discrete
 * equilibrium of the quick grid (where a symmetry's zero mode is exact to round-off) it
 * is neutral when that one eigenvalue lies within TR_STAB_NEUTRAL of zero and no other
 * within the band: stable when none lies below, the margin left to the full test.
 * Returns 1 when decided. */
static int quick_neutral(const tr_model *m, tr_data *d, struct tr_stab_ws *w, int nn, double band)
{
    int lo, hi, a, b, sing;
    tr_stab_discrete_equilibrium(m, w, nn, 3);
    lo = tr_btd_count(&w->h, -band, &sing);
    if (sing) return 0;
    hi = tr_btd_count(&w->h, band, &sing);
    if (sing || hi - lo != 1) return 0;
    a = tr_btd_count(&w->h, -TR_STAB_NEUTRAL, &sing);
    if (sing || a != lo) return 0;
    b = tr_btd_count(&w->h, TR_STAB_NEUTRAL, &sing);
    if (sing || b != hi) return 0;
    d->stable = lo == 0;
    d->stab_index = lo;
    d->stab_gap = 0.0; /* a zero mode: a kept verdict would not see it move */
    snprintf(d->stab_reason, sizeof d->stab_reason,
             "%s: a direction of zero stiffness (a symmetry of the scene), %d negative %s, no "
             "other eigenvalue within %.2g EI/L of zero",
             lo ? "unstable" : "neutrally stable", lo, lo == 1 ? "mode" : "modes", band);
    return 1;
}

/* No eigenvalue within band 2^j (j >= 1) of zero but the n0 below it.  With none below
 * -band (n0 = 0) none lies below -band 2^j either (the count is monotone in the shift):
 * only the upper side is counted then. */
static int clear_within(tr_btd *h, double band, int j, int n0)
{
    int sing, c;
    if (n0 > 0) {
        c = tr_btd_count(h, -ldexp(band, j), &sing);
        if (sing || c != n0) return 0;
    }
    c = tr_btd_count(h, ldexp(band, j), &sing);
    return !sing && c == n0;
}

/* The quick test: Kirchhoff elements on a coarse grid (TR_STAB_QUICK elements, doubled
 * while an element turns too much), no refinement; decides only when no eigenvalue lies
 * within +-TR_STAB_QUICK_BAND (1 + stiffness scale), where neither the model reduction
 * (shear and extension, O((d/L)^2)) nor the coarse grid's error can move one across
 * zero.  Returns 1 when decided (the margin stays NaN: the full test gives it on
 * request). */
static int verdict_quick(const tr_model *m, tr_data *d, double *band_out)
{
    const double band = TR_STAB_QUICK_BAND * (1.0 + tr_stiffness_scale(m, d));
    double gap;
    int nuni = TR_STAB_QUICK, nn, j, n0, nlo, nhi, sing, jmax = 0, jlo = 0;
    struct tr_stab_ws *w;
    *band_out = 0.0;
    for (;;) {
        w = tr_stab_workspace(m, d, &d->stab_quick, nuni, 0);
        if (!w || tr_record_coarse(m, w->rec, d->x, d->steps, shooting_tip(d)) != TR_OK) return 0;
        for (nn = j = 0; j < w->ngrid; j++) w->node[nn++] = j;
        if (tr_stab_level_setup(m, d, w, nn) == 0) break;
        if (2 * nuni > TR_STAB_MAX_ELEMENTS) return 0;
        nuni *= 2;
    }
    tr_stab_assemble(m, w, nn, 3);
    nlo = tr_btd_count(&w->h, -band, &sing);
    if (sing) return 0;
    nhi = tr_btd_count(&w->h, band, &sing);
    if (sing || nlo < 0) return 0;
    if (nhi - nlo == 1) return quick_neutral(m, d, w, nn, band);
    *band_out = band; /* its Hessian stays the recorded state's, for verdict_check */
    if (nlo != nhi) return 0;
    n0 = nlo;
    /* how far from zero the nearest eigenvalue lies, in doublings of the band (a verdict
     * kept by warm solves lasts as long as their change stays small against it): the
     * largest band 2^j (up to TR_STAB_QUICK_GAP band) clear of eigenvalues but the n0
     * below zero.  Being clear is monotone in j: the cap first (the common case, one
     * count), then a bisection on j. */
    while (ldexp(1.0, jmax) < TR_STAB_QUICK_GAP) jmax++;
    if (clear_within(&w->h, band, jmax, n0)) {
        jlo = jmax;
    } else {
        int jhi = jmax;
        while (jhi - jlo > 1) {
            const int mid = (jlo + jhi) / 2;
            if (clear_within(&w->h, band, mid, n0))
                jlo = mid;
            else
                jhi = mid;
        }
    }
    gap = ldexp(band, jlo);
    d->stable = n0 == 0;
    d->stab_index = n0;
    d->stab_gap = gap;
    snprintf(d->stab_reason, sizeof d->stab_reason,
             "%s: %d negative %s, no eigenvalue within %.2g EI/L of zero",
             n0 ? "unstable" : "stable", n0, n0 == 1 ? "mode" : "modes", gap);
    return 1;
}

/* Where the quick test's a priori band is too wide to decide (a large load-induced
 * stiffness scale widens it), an a posteriori one: the smallest eigenvalue at the
 * recorded state on the quick grid (mc, its Hessian still in wq) and on the full test's
 * first grid of twice the elements (mf), both without the discrete equilibrium (it
 * moves them by O(h^2), which the two grids' difference measures with the rest of
 * the discretisation error).  Decides only a stable solution whose smallest eigenvalue
 * lies beyond TR_STAB_POST times the estimated error (Richardson's |mf - mc| / 3, plus
 * the Kirchhoff elements' neglect of shear and extension on a Cosserat rod), on both
 * grids; the margin is left to the full test (NaN).  Returns 1 when decided. */
/* The smallest eigenvalue of a pencil without negative ones bracketed in [*lo, *hi]
 * (count(*lo) = 0 < count(*hi) on entry) to TR_STAB_POST_RTOL of it, by bisection on
 * the inertia; 0 when a count is singular. */
static int bracket_smallest(tr_btd *h, double *lo, double *hi)
{
    int sing, it;
    for (it = 0; it < 60 && *hi - *lo > 1e-9 + TR_STAB_POST_RTOL * *hi; it++) {
        const double mid = 0.5 * (*lo + *hi);
        const int cnt = tr_btd_count(h, mid, &sing);
        if (sing) return 0;
        if (cnt >= 1)
            *hi = mid;
        else
            *lo = mid;
    }
    return 1;
}

static int verdict_check(const tr_model *m, tr_data *d, struct tr_stab_ws *wq, double band)
{
    const double scale = 1.0 + tr_stiffness_scale(m, d);
    const int nuni = d->stab ? d->stab->nuni : TR_STAB_ELEMENTS;
    double clo = 0.0, chi = band, flo, fhi, err, reduction = 0.0;
    int n, nn, j, sing;
    struct tr_stab_ws *w;
    if (nuni != 2 * wq->nuni) return 0;
    /* the quick grid: none below 0, some below band (why the quick test did not decide) */
    n = tr_btd_count(&wq->h, 0.0, &sing);
    if (sing || n != 0) return 0;
    if (!bracket_smallest(&wq->h, &clo, &chi)) return 0;
    /* an eigenvalue this close to zero on the coarse grid is the full test's (a
     * symmetry's zero mode, or a margin within its discretisation error) */
    if (!(clo > TR_STAB_POST_MIN * band)) return 0;
    w = tr_stab_workspace(m, d, &d->stab, nuni, 0);
    if (!w) return 0;
    /* recorded like the quick grid (the full test records this workspace to the shooting
     * accuracy) */
    if (tr_record_coarse(m, w->rec, d->x, d->steps, shooting_tip(d)) != TR_OK) return 0;
    for (nn = j = 0; j < w->ngrid; j++) w->node[nn++] = j;
    if (tr_stab_level_setup(m, d, w, nn) < 0) return 0;
    tr_stab_assemble(m, w, nn, 3);
    /* the finer grid's smallest eigenvalue, bracketed near the coarse one's first */
    flo = 0.5 * clo, fhi = 2.0 * chi;
    n = tr_btd_count(&w->h, flo, &sing);
    if (sing || n != 0) return 0;
    n = tr_btd_count(&w->h, fhi, &sing);
    if (sing || n < 1) return 0;
    if (!bracket_smallest(&w->h, &flo, &fhi)) return 0;
    if (!m->kirchhoff) reduction = scale * m->EI * (1.0 / m->GA + 1.0 / m->EA) / (m->L * m->L);
    /* Richardson's estimate from the widest difference the brackets allow */
    err = fmax(fabs(fhi - clo), fabs(chi - flo)) / 3.0 + reduction;
    if (!(flo > TR_STAB_POST * err)) return 0;
    d->stable = 1;
    d->stab_index = 0;
    d->stab_gap = flo - TR_STAB_POST * err;
    snprintf(d->stab_reason, sizeof d->stab_reason,
             "stable: 0 negative modes, no eigenvalue within %.2g EI/L of zero (on %d and %d "
             "elements, discretisation error about %.2g)",
             d->stab_gap, wq->nuni, nuni, err);
    return 1;
}

/* The quick test, then the a posteriori check, then the full test. */
static void verdict_quick_or_full(const tr_model *m, tr_data *d)
{
    double band;
    if (verdict_quick(m, d, &band)) return;
    if (band > 0.0 && verdict_check(m, d, d->stab_quick, band)) return;
    verdict_full(m, d, 1);
}

/* Unstable with tendons at their switch: the sides they resist tested too (tr_switch.c);
 * otherwise the note that the slack side was tested. */
static void switch_or_note(const tr_model *m, tr_data *d)
{
    if (d->stable == 0 && tr_switch_count(m, d) > 0)
        tr_switch_verdict(m, d);
    else
        slack_side_note(m, d);
}

/* Channel friction has no energy whose minimum decides stability (a sound test for it,
 * e.g. on the stick/slip cone, is not known here): the state is not tested, and the
 * verdict of its frictionless twin -- the same state and tensions, the energy without
 * friction -- is reported in d->stab_twin and the reason.  An unstable twin means that
 * friction alone holds the state, if it does. */
static void friction_twin(const tr_model *m, tr_data *d, int quick)
{
    char twin[120];
    const char *r;
    size_t n;
    const double g = tr_friction_exponent(m);
    if (!(g <= TR_TWIN_FRIC_MAX)) {
        snprintf(d->stab_reason, sizeof d->stab_reason,
                 "not tested: friction in the tendon channels is not conservative, and it "
                 "changes the tensions like e^%.3g along them: no frictionless state is "
                 "close enough to compare",
                 g);
        return;
    }
    if (quick)
        verdict_quick_or_full(m, d);
    else
        verdict_full(m, d, 0);
    d->stab_twin = d->stable;
    d->stab_twin_margin = d->stability;
    d->stab_twin_index = d->stab_index;
    r = d->stab_reason[0] ? d->stab_reason : "not decided";
    n = strlen(r) < sizeof twin - 1 ? strlen(r) : sizeof twin - 1;
    memcpy(twin, r, n);
    twin[n] = '\0';
    d->stable = -1;
    d->stability = NAN;
    d->stab_index = -1;
    d->stab_gap = 0.0;
    snprintf(d->stab_reason, sizeof d->stab_reason,
             "not tested: friction in the tendon channels is not conservative; the "
             "frictionless twin of this state (mu = 0, the same tensions) is %s",
             twin);
}

void tr_stability(const tr_model *m_, tr_data *d)
{
    const tr_model *m = TR_IN(m_, d);
    verdict_reset(d);
    if (not_conservative(m, d)) return;
    tr_set_tensions(m, d, d->x);
    if (m->nfric > 0) {
        friction_twin(m, d, 0);
        return;
    }
    verdict_full(m, d, 0);
    switch_or_note(m, d);
}

void tr_stability_quick(const tr_model *m_, tr_data *d)
{
    const tr_model *m = TR_IN(m_, d);
    verdict_reset(d);
    if (not_conservative(m, d)) return;
    tr_set_tensions(m, d, d->x);
    if (m->nfric > 0) {
        friction_twin(m, d, 1);
        return;
    }
    verdict_quick_or_full(m, d);
    switch_or_note(m, d);
}

int tr_stability_of(const tr_model *m_, tr_data *d, const double *x, int steps, int quick)
{
    const tr_model *m = TR_IN(m_, d);
    int i;
    if (!TR_OWNS(m, d) || steps < 1 || steps > TR_MAX_STEPS) {
        tr_set_message(d,
                       "tr_stability_of: a workspace of another model, or steps = %d out of "
                       "range",
                       steps);
        return TR_EINVAL;
    }
    tr_solve_reset(m, d, steps);
    memcpy(d->x, x, (size_t)d->k * sizeof(double));
    for (i = 0; i < d->k; i++)
        if (!isfinite(x[i])) {
            snprintf(d->stab_reason, sizeof d->stab_reason, "not tested: no solution");
            return TR_OK;
        }
    if (quick) {
        /* the shooting end state at x, as a solve's verdict has it (its grids' recording
         * is checked against it; without one they are recorded to the shooting accuracy) */
        (void)tr_residual(m, d, d->x, d->ft);
        tr_stability_quick(m, d);
    } else
        tr_stability(m, d);
    return TR_OK;
}
