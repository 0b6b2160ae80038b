/*
 * tr_record.c -- the recording pass: the states at the output nodes of a solved
 * scene, integrated from the converged unknowns with the accuracy of the shooting
 * steps (denser nodes cost RK4 steps instead of rk8 ones), the tip node being the
 * shooting tip itself; or only the tip, from the last residual evaluation.
 */
#include <math.h>
#include <string.h>

#include "tendonrod.h"
#include "tr_internal.h"
#include "tr_stab.h"

static void store_node(const tr_model *m, tr_data *d, int j, const double *y)
{
    const double sj = d->s[j], eps = 1e-12 * m->L;
    int i;
    tr_state_world(m, y, d->pos + 3 * j, d->rot + 9 * j, d->force + 3 * j, d->moment + 3 * j);
    for (i = 0; i < m->nt; i++) {
        const int f = m->tendon[i].fric_index;
        d->node_tension[m->nt * j + i] =
            sj <= m->tendon[i].t + eps ? tr_tension_at(m, d, i, y) : 0.0;
        /* the rest lengths are states of the recording layout only (the shooting tip that
         * replaces the recorded one keeps the recorded rest length) */
        if (d->rec)
            d->node_rest[m->nt * j + i] = f >= 0 ? y[m->n_base + m->nt + m->nfric + f] : NAN;
    }
}

/* Integrate a span [s0, s1] of segment k in the recording pass with at least the
 * accuracy of the shooting steps (a stability grid's: rec_coarse).  Fixed-step rk8: where nodes are dense, a few
 * classical RK4 steps of at most an eighth of the shooting step cost less than
 * one 13-stage rk8 step and stay as accurate (error ~ (h/8)^4 against h^8 for
 * the curvatures of a robot); where nodes are sparse, rk8 at the shooting step. */
static int record_span(const tr_model *m, tr_data *d, double s0, double s1, int k, double *y,
                       int allow_rk4, int *used_rk4)
{
    const double len = s1 - s0;
    const double h = (m->bp[k + 1] - m->bp[k]) / tr_segment_steps(m, d, k);
    int n8, n4;
    if (!(len > 0.0)) return TR_OK;
    n8 = (int)ceil(len / h - 1e-9);
    if (n8 < 1) n8 = 1;
    if (d->opt.integrator != TR_RK8) return tr_integrate(m, d, s0, s1, n8, y);
    n4 = d->rec_coarse
             ? (int)ceil(len / (h * TR_RECORD_COARSE_FRACTION) - 1e-9)
             : (int)ceil(len / fmin(h / TR_RECORD_RK4_FRACTION, m->L / TR_RECORD_RK4_MIN_STEPS) -
                         1e-9);
    if (n4 < 1) n4 = 1;
    if (!allow_rk4 || 4 * n4 * (d->rec_coarse ? 2 : 1) >= 13 * n8)
        return tr_integrate(m, d, s0, s1, n8, y);
    *used_rk4 = 1;
    return tr_integrate_with(m, d, TR_RK4, s0, s1, n4, y);
}

/* Restart the recording at shooting node j from its unknowns; the recording
 * layout has a path-length slot per tendon: those of displacement-controlled
 * tendons come from the node, the others keep integrating (they are continuous);
 * the friction deficits come from the node. */
static void rec_restart(const tr_model *m, tr_data *d, int j, double *y)
{
    const int o = tr_node_off(m, j), lenbase = m->n_base, nb = m->n_base + m->ndisp;
    int c, i;
    for (c = 0; c < m->n_base; c++) y[c] = d->x[o + c] * tr_node_scale(m, c);
    for (i = 0; i < m->nt; i++) {
        const tr_tendon *t = &m->tendon[i];
        if (t->len_index >= 0) y[lenbase + i] = d->x[o + m->n_base + t->len_index] * m->len_s;
    }
    for (c = 0; c < m->nfric; c++)
        y[m->n_base + m->nt + c] = d->x[o + nb + c] * tr_node_scale(m, nb + c);
}

static int record_pass(const tr_model *m, tr_data *d, int allow_rk4, int *used)
{
    const double eps = 1e-12 * m->L;
    const int nn = d->nnode, lenbase = m->planar ? TR_YP_LEN : TR_Y_LEN;
    double *y = d->y, scur = 0.0;
    int j, k = 0, status = TR_OK, i, used_rk4 = 0;

    d->rec = 1;
    d->y_steps = -1; /* y becomes the recording state */
    tr_set_tensions(m, d, d->x);
    tr_init_state(m, d, d->x, y, m->n_states_rec);
    for (j = 0; j < nn && status == TR_OK; j++) {
        const double sj = d->s[j];
        while (k < m->nseg - 1 && sj > m->bp[k + 1] + eps && status == TR_OK) {
            d->seg = k;
            status = record_span(m, d, scur, m->bp[k + 1], k, y, allow_rk4, &used_rk4);
            tr_apply_jump(m, d, k + 1, y);
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
                tr_apply_jump(m, d, k + 1, y);
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
            tr_apply_jump(m, d, k + 1, y);
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
        if (t->control == TR_DISPLACEMENT && t->target_row >= 0)
            d->displacement[i] = tr_target_displacement(m, d, i, y[lenbase + i]);
        else if (t->control == TR_DISPLACEMENT)
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
        for (j = 0; j < 2 * m->nt * nn; j++) d->node_tension[j] = NAN;
    }
    return status;
}

/* The recording pass; if it took RK4 shortcuts (dense nodes), its tip is checked
 * against the shooting integration's tip: redone at the shooting steps when they
 * differ grossly (> TR_RECORD_GROSS, scaled), else the tip node is replaced by the
 * shooting tip. */
int tr_record(const tr_model *m_, tr_data *d)
{
    const tr_model *m = TR_IN(m_, d);
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

int tr_record_coarse(const tr_model *m_, tr_data *d, const double *x, int steps, const double *tip)
{
    const tr_model *m = TR_IN(m_, d);
    int used = 0, st, i;
    double diff = 0.0;
    if (!tip || tr_state_from(m, d, x, steps) != TR_OK) return tr_record_from(m, d, x, steps);
    d->rec_coarse = 1;
    st = record_pass(m, d, 1, &used);
    d->rec_coarse = 0;
    if (st != TR_OK || !used) return st;
    for (i = 0; i < m->n_base; i++) {
        const double e = fabs(d->y[i] - tip[i]) / m->xstate_scale[i];
        if (e > diff) diff = e;
    }
    return diff <= TR_RECORD_COARSE_TOL ? TR_OK : tr_record(m, d);
}

int tr_tip_state(const tr_model *m_, tr_data *d)
{
    const tr_model *m = TR_IN(m_, d);
    double *t = d->tip;
    const int lenbase = m->planar ? TR_YP_LEN : TR_Y_LEN;
    int i;
    /* the last shooting evaluation at the solution left its end state in y; otherwise
     * one more evaluation (the tip the residual and the tolerance refer to) */
    if (!tr_holds_end_state(d, d->x)) {
        const int st = tr_residual(m, d, d->x, d->ft);
        if (st != TR_OK) {
            for (i = 0; i < 18; i++) t[i] = NAN;
            d->tip_angle = NAN;
            return st;
        }
    } else {
        tr_set_tensions(m, d, d->x);
    }
    tr_state_world(m, d->y, t, t + 3, t + 12, t + 15);
    d->tip_angle = m->planar ? d->y[TR_YP_TH] : NAN;
    for (i = 0; i < m->nt; i++) {
        const tr_tendon *td = &m->tendon[i];
        d->tension[i] = d->tau[i];
        d->slack[i] = d->beta[i];
        d->displacement[i] = td->control != TR_DISPLACEMENT ? NAN
                             : td->target_row >= 0
                                 ? tr_target_displacement(m, d, i, d->y[lenbase + td->len_index])
                                 : td->value;
    }
    return TR_OK;
}

int tr_record_tip(const tr_model *m_, tr_data *d)
{
    const tr_model *m = TR_IN(m_, d);
    int st;
    if (d->nnode != 1 || !(fabs(d->s[0] - m->L) <= 1e-12 * m->L)) {
        tr_set_message(d, "tr_record_tip needs a tip-only workspace");
        return TR_EINVAL;
    }
    st = tr_tip_state(m, d);
    memcpy(d->pos, d->tip, 3 * sizeof(double));
    memcpy(d->rot, d->tip + 3, 9 * sizeof(double));
    memcpy(d->force, d->tip + 12, 3 * sizeof(double));
    memcpy(d->moment, d->tip + 15, 3 * sizeof(double));
    if (st == TR_OK) {
        int i;
        for (i = 0; i < m->nt; i++) /* the end state of the shooting layout */
            d->node_tension[i] =
                fabs(m->tendon[i].t - m->L) <= 1e-12 * m->L ? tr_tension_at(m, d, i, d->y) : 0.0;
    }
    return st;
}

int tr_state_from(const tr_model *m_, tr_data *d, const double *x, int steps)
{
    const tr_model *m = TR_IN(m_, d);
    int i;
    if (!TR_OWNS(m, d) || steps < 1 || steps > TR_MAX_STEPS) {
        tr_set_message(d,
                       "a state from unknowns: a workspace of another model, or steps = %d "
                       "out of range",
                       steps);
        return TR_EINVAL;
    }
    tr_solve_reset(m, d, steps);
    memcpy(d->x, x, (size_t)d->k * sizeof(double));
    for (i = 0; i < d->k; i++)
        if (!isfinite(x[i])) return TR_ENONFINITE;
    return TR_OK;
}

int tr_record_from(const tr_model *m_, tr_data *d, const double *x, int steps)
{
    const tr_model *m = TR_IN(m_, d);
    int i;
    const int st = tr_state_from(m, d, x, steps);
    if (st == TR_ENONFINITE) {
        /* a solve that failed before it had unknowns (a scene without a unique
         * equilibrium): its states are NaN */
        for (i = 0; i < 18 * d->nnode; i++) d->pos[i] = NAN;
        for (i = 0; i < 3 * m->nt; i++) d->tension[i] = NAN;
    }
    if (st != TR_OK) return st;
    return tr_record(m, d);
}
