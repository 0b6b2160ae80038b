/*
 * tr_inputs.c -- the inputs of a workspace: every value that changes between calls; and
 * the accessors of the opaque workspace (what a caller reads of it).
 *
 * A compiled model is constant: its structure (sections, routes, control kinds, which
 * tendons have friction, the load positions, the shooting segments) and the values it
 * was compiled with, the defaults.  A workspace holds the values its solves use in
 * d->in, a tr_model by value that the solver reads in place of the compiled one (the
 * entry points swap it in, TR_IN): its structure arrays are the compiled model's own
 * (const, shared by every workspace and thread), its value arrays -- the tendons (their
 * actuation, pretension, rest lengths, friction coefficient, target rows), the point
 * loads and their breakpoint sums, the distributed loads and their segment sums, the
 * target -- are the workspace's, copied from the defaults by tr_data_alloc.  A setter
 * writes them and what follows from them (breakpoint sums, rest lengths, the scene
 * checks); nothing else is recomputed per call.
 *
 * A design perturbation (linearisation, a path over a design parameter) changes the
 * rigidities or a tendon's geometry, which enter precomputed data: the per-segment
 * rigidities (seg_rod, from the sections) and the tendons' base frames and rest lengths.
 * The view then points at workspace-owned copies of the sections and seg_rod (allocated
 * with the workspace), the perturbed values are derived there, and tr_inputs_restore
 * puts back the saved view and tendons (the pointers at the compiled arrays again):
 * two copies of O(nseg + nt) numbers per perturbed evaluation.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tendonrod.h"
#include "tr_internal.h"

/* The values a set would set, checked first so that a refused set changes nothing. */
static int check_values(const tr_model *m, const double *value, const double *load,
                        const double *dist, char *msg, size_t msglen)
{
    int i, c;
    for (i = 0; value && i < m->nt; i++) {
        if (!isfinite(value[i])) {
            tr_msgf(msg, msglen, "tendon %d value %g is not finite", i, value[i]);
            return TR_EINVAL;
        }
        if (m->tendon[i].control == TR_TENSION && value[i] < 0.0) {
            tr_msgf(msg, msglen, "tendon %d tension = %g N must be >= 0 (a tendon cannot push)", i,
                    value[i]);
            return TR_EINVAL;
        }
    }
    for (i = 0; load && i < m->nl; i++) {
        const double *l = load + 6 * i;
        for (c = 0; c < 6; c++)
            if (!isfinite(l[c])) {
                tr_msgf(msg, msglen, "load %d component %d = %g is not finite", i, c, l[c]);
                return TR_EINVAL;
            }
        if (m->planar && (l[1] != 0.0 || l[3] != 0.0 || l[5] != 0.0)) {
            tr_msgf(msg, msglen,
                    "load %d leaves the x-z plane (Fy, Mx or Mz nonzero) but the model was "
                    "compiled planar; compile it with force_spatial",
                    i);
            return TR_EINVAL;
        }
    }
    if (dist) {
        for (c = 0; c < 3; c++)
            if (!isfinite(dist[c])) {
                tr_msgf(msg, msglen, "dist[%d] = %g is not finite", c, dist[c]);
                return TR_EINVAL;
            }
        if (m->planar && dist[1] != 0.0) {
            tr_msgf(msg, msglen,
                    "distributed load has a y component %g but the model was compiled planar; "
                    "compile it with force_spatial",
                    dist[1]);
            return TR_EINVAL;
        }
    }
    return TR_OK;
}

/* The values into m (a compiled model's defaults or a workspace's view), checked. */
static int set_values(tr_model *m, const double *value, const double *load, const double *dist,
                      char *msg, size_t msglen)
{
    int i, c;
    if (check_values(m, value, load, dist, msg, msglen) != TR_OK) return TR_EINVAL;
    for (i = 0; value && i < m->nt; i++) m->tendon[i].value = value[i];
    if (load) {
        for (i = 0; i < m->nl; i++)
            for (c = 0; c < 6; c++) m->load[TR_LD_NCOL * i + TR_LD_F + c] = load[6 * i + c];
        tr_sum_breakpoint_loads(m);
    }
    if (dist) {
        memcpy(m->dist, dist, 3 * sizeof(double));
        m->has_dist = (dist[0] != 0.0 || dist[1] != 0.0 || dist[2] != 0.0);
    }
    /* the pretension check does not depend on values; the indeterminacy check does */
    if (m->scene_status != TR_EPRETENSION && value) {
        m->scene_message[0] = '\0';
        m->scene_status = tr_check_indeterminate(m, m->scene_message, sizeof m->scene_message);
    }
    return TR_OK;
}

static int set_pretension(tr_model *m, const double *pretension, char *msg, size_t msglen)
{
    int i, status;
    for (i = 0; i < m->nt; i++)
        if (!(pretension[i] >= 0.0 && isfinite(pretension[i]))) {
            tr_msgf(msg, msglen, "tendon %d pretension = %g N must be finite and >= 0", i,
                    pretension[i]);
            return TR_EINVAL;
        }
    for (i = 0; i < m->nt; i++) m->tendon[i].pretension = pretension[i];
    m->scene_message[0] = '\0';
    status = tr_rest_lengths(m, m->scene_message, sizeof m->scene_message);
    if (status == TR_OK)
        status = tr_check_indeterminate(m, m->scene_message, sizeof m->scene_message);
    m->scene_status = status;
    return TR_OK;
}

int tr_model_set_values(tr_model *m, const double *value, const double *load, const double *dist,
                        char *msg, size_t msglen)
{
    return set_values(m, value, load, dist, msg, msglen);
}

int tr_model_set_pretension(tr_model *m, const double *pretension, char *msg, size_t msglen)
{
    return set_pretension(m, pretension, msg, msglen);
}

tr_model *tr_inputs_view(const tr_model *m, tr_data *d, char *msg, size_t msglen)
{
    if (!d || !m || (m != d->model && m != d->vm) || d->vm != &d->in) {
        tr_msgf(msg, msglen, "the workspace was not allocated for this model");
        return NULL;
    }
    tr_inputs_restore(d);
    return &d->in;
}

int tr_data_set_values(const tr_model *m, tr_data *d, const double *value, const double *load,
                       const double *dist, char *msg, size_t msglen)
{
    tr_model *v = tr_inputs_view(m, d, msg, msglen);
    return v ? set_values(v, value, load, dist, msg, msglen) : TR_EINVAL;
}

int tr_data_set_pretension(const tr_model *m, tr_data *d, const double *pretension, char *msg,
                           size_t msglen)
{
    tr_model *v = tr_inputs_view(m, d, msg, msglen);
    return v ? set_pretension(v, pretension, msg, msglen) : TR_EINVAL;
}

/* ------------------------------------------------------------------ the view */
static size_t nb3(const tr_model *m)
{
    return (size_t)3 * (m->nseg + 1);
}

int tr_inputs_alloc(const tr_model *m, tr_data *d)
{
    const size_t nt = (size_t)(m->nt > 0 ? m->nt : 1);
    const size_t nl = (size_t)TR_LD_NCOL * m->nl, nd = (size_t)TR_DL_NCOL * m->nd;
    const size_t nsp = (size_t)3 * (m->nseg > 0 ? m->nseg : 1);
    const size_t nsec = (size_t)TR_SC_NCOL * m->nsec, nsr = (size_t)TR_SR_NCOL * m->nseg;
    double *q;
    if (m->view) {
        /* a nested workspace (the stability test's) of another workspace's view: it reads
         * that view, whose values its owner sets */
        d->vm = m;
        return 0;
    }
    d->in_tendon = (tr_tendon *)malloc(2 * nt * sizeof(tr_tendon));
    d->in_block = (double *)malloc((nl + 2 * nb3(m) + nd + nsp + nsec + nsr + 1) * sizeof(double));
    if (!d->in_tendon || !d->in_block) return -1;
    d->in = *m;
    d->in.view = 1;
    d->in.tendon = d->in_tendon;
    d->in_tendon_save = d->in_tendon + nt;
    q = d->in_block;
    d->in.load = q, q += nl;
    d->in.bpF = q, q += nb3(m);
    d->in.bpM = q, q += nb3(m);
    d->in.dload = q, q += nd;
    d->in.seg_pdist = q, q += nsp;
    d->in_sec = q, q += nsec;
    d->in_seg_rod = q;
    d->vm = &d->in;
    tr_data_reset_inputs(m, d);
    return 0;
}

void tr_inputs_free(tr_data *d)
{
    free(d->in_tendon);
    free(d->in_block);
}

void tr_data_reset_inputs(const tr_model *m, tr_data *d)
{
    tr_model *v = &d->in;
    (void)m;
    if (d->vm != &d->in) return;
    m = d->model;
    memcpy(v->tendon, m->tendon, (size_t)m->nt * sizeof(tr_tendon));
    memcpy(v->load, m->load, (size_t)TR_LD_NCOL * m->nl * sizeof(double));
    memcpy(v->bpF, m->bpF, nb3(m) * sizeof(double));
    memcpy(v->bpM, m->bpM, nb3(m) * sizeof(double));
    memcpy(v->dload, m->dload, (size_t)TR_DL_NCOL * m->nd * sizeof(double));
    memcpy(v->seg_pdist, m->seg_pdist, (size_t)3 * (m->nseg > 0 ? m->nseg : 1) * sizeof(double));
    memcpy(v->dist, m->dist, sizeof v->dist);
    v->has_dist = m->has_dist;
    v->has_pdist = m->has_pdist;
    v->target_kind = m->target_kind;
    memcpy(v->target, m->target, sizeof v->target);
    v->scene_status = m->scene_status;
    memcpy(v->scene_message, m->scene_message, sizeof v->scene_message);
    d->in_perturbed = 0;
}

void tr_inputs_copy(tr_data *dst, const tr_model *src)
{
    tr_model *v = &dst->in;
    int i;
    for (i = 0; i < src->nt; i++) {
        v->tendon[i].value = src->tendon[i].value;
        v->tendon[i].pretension = src->tendon[i].pretension;
        v->tendon[i].rest = src->tendon[i].rest;
        v->tendon[i].rest_dev = src->tendon[i].rest_dev;
        v->tendon[i].target_row = src->tendon[i].target_row;
        v->tendon[i].mu = src->tendon[i].mu;
    }
    v->target_kind = src->target_kind;
    memcpy(v->target, src->target, sizeof v->target);
    memcpy(v->load, src->load, (size_t)TR_LD_NCOL * src->nl * sizeof(double));
    tr_sum_breakpoint_loads(v);
    memcpy(v->dist, src->dist, sizeof v->dist);
    v->has_dist = src->has_dist;
    v->scene_status = src->scene_status;
    memcpy(v->scene_message, src->scene_message, sizeof v->scene_message);
}

void tr_inputs_restore(tr_data *d)
{
    if (!d->in_perturbed) return;
    memcpy(d->in.tendon, d->in_tendon_save, (size_t)d->in.nt * sizeof(tr_tendon));
    d->in = d->in_save;
    d->in_perturbed = 0;
}

int tr_inputs_perturb(tr_data *d, int kind, int index, double delta)
{
    tr_model *mp = &d->in;
    if (d->vm != &d->in) return TR_EINVAL;
    tr_inputs_restore(d);
    if (delta == 0.0) return TR_OK;
    /* a backbone of several sections has a rigidity per section, not one for the rod; a
     * single (precurved) section is the rod */
    if (mp->nsec > 1 && kind >= TR_PAR_ROD_EI && kind <= TR_PAR_ROD_GA) return TR_EINVAL;
    if (kind == TR_PAR_FRICTION && mp->tendon[index].fric_index < 0) return TR_EINVAL;
    if ((kind == TR_PAR_OFFSET || kind == TR_PAR_SLOPE) &&
        mp->tendon[index].route == TR_ROUTE_PIECE)
        return TR_EINVAL; /* a piecewise path has no offset or slope */
    if (kind < TR_PAR_ROD_EI || kind >= TR_PAR_NKIND) return TR_EINVAL;
    /* the view and its tendons saved; the sections and seg_rod the view's own copies */
    d->in_save = d->in;
    memcpy(d->in_tendon_save, mp->tendon, (size_t)mp->nt * sizeof(tr_tendon));
    memcpy(d->in_sec, mp->sec, (size_t)TR_SC_NCOL * mp->nsec * sizeof(double));
    mp->sec = d->in_sec;
    mp->seg_rod = d->in_seg_rod;
    d->in_perturbed = 1;
    switch (kind) {
    case TR_PAR_ROD_EI:
        mp->EI += delta;
        if (mp->nsec == 1) mp->sec[TR_SC_EI] += delta;
        break;
    case TR_PAR_ROD_GJ:
        mp->GJ += delta;
        if (mp->nsec == 1) mp->sec[TR_SC_GJ] += delta;
        break;
    case TR_PAR_ROD_EA:
        mp->EA += delta;
        if (mp->nsec == 1) mp->sec[TR_SC_EA] += delta;
        break;
    case TR_PAR_ROD_GA:
        mp->GA += delta;
        if (mp->nsec == 1) mp->sec[TR_SC_GA] += delta;
        break;
    case TR_PAR_TENDON_EA: mp->tendon[index].EA += delta; break;
    case TR_PAR_FRICTION: mp->tendon[index].mu += delta; break;
    case TR_PAR_OFFSET:
    case TR_PAR_SLOPE: {
        tr_tendon *t = &mp->tendon[index];
        if (kind == TR_PAR_OFFSET)
            t->b += delta;
        else
            t->a += delta;
        t->wref = sqrt(1.0 + t->a * t->a);
        tr_tendon_base_frame_straight(t);
        if (mp->precurved || t->route != TR_ROUTE_LINEAR) tr_tendon_base_frame(mp, index);
        if (mp->planar) {
            t->t0[1] = 0.0;
            t->rt0[0] = 0.0;
        }
        break;
    }
    default: break;
    }
    tr_fill_segment_rods(mp);
    if (tr_rest_lengths(mp, NULL, 0) == TR_OK) return TR_OK;
    tr_inputs_restore(d);
    return TR_EINVAL;
}

/* ------------------------------------------------------ reading a workspace */
void tr_data_result(const tr_data *d, tr_result *r)
{
    r->status = d->status;
    r->nit = d->nit, r->nfev = d->nfev, r->njev = d->njev;
    r->cont_steps = d->cont_steps;
    r->steps = d->steps;
    r->ver_carried = d->ver_carried;
    r->work = d->spent;
    r->residual_norm = d->residual_norm;
    r->jacobian_cond = d->jacobian_cond;
    r->truncation = d->truncation;
    r->message = d->message;
}

void tr_data_outputs(const tr_data *d, tr_outputs *o)
{
    o->nnode = d->nnode, o->k = d->k, o->lazy = d->lazy;
    o->s = d->s, o->pos = d->pos, o->rot = d->rot, o->force = d->force, o->moment = d->moment;
    o->node_tension = d->node_tension, o->node_rest = d->node_rest;
    o->tension = d->tension, o->slack = d->slack, o->displacement = d->displacement;
    o->tip = d->tip, o->tip_angle = d->tip_angle;
    o->x = d->x, o->J = d->J;
}

void tr_data_verdict(const tr_data *d, tr_verdict *v)
{
    v->stable = d->stable, v->index = d->stab_index;
    v->margin = d->stability;
    v->reason = d->stab_reason;
}

int tr_data_verified(const tr_data *d, tr_verified *v)
{
    v->steps = d->have_ver ? d->steps_ver : 0;
    v->estimate = d->est_ver;
    v->x = d->x_ver;
    v->values = d->have_ver && d->have_val_ver ? d->val_ver : NULL;
    return d->have_ver;
}

const char *tr_data_carry_reason(const tr_data *d)
{
    return d->carry_valid ? d->carry_reason : NULL;
}

const tr_options *tr_data_options(const tr_data *d)
{
    return &d->opt;
}

const char *tr_data_message(const tr_data *d)
{
    return d->message;
}

int tr_data_has_last(const tr_data *d)
{
    return d->have_last;
}

void tr_data_set_lazy(tr_data *d, int lazy)
{
    d->lazy = lazy != 0;
}

void tr_data_set_polish_once(tr_data *d, int polish_once)
{
    d->polish_once = polish_once != 0;
}
