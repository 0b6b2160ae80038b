/*
 * tr_friction.c -- Coulomb friction between the tendons and their channels
 * (docs/model.md, Section 3): the friction states of a model, and the tensions
 * along s they give.
 *
 * A tendon with mu > 0 slides through its channel in one direction along its whole
 * length (+1 in, toward the actuator; -1 out).  The channel presses on it with
 * tau |t^'| per unit backbone length (t^' the derivative of its world tangent along
 * s), and friction changes its tension by d tau/ds = -slide mu tau |t^'|.  Its state
 * is the deficit delta = tau(0) - tau(s), 0 at the base: the tension at the actuator
 * stays the tendon's tension (prescribed, or the unknown of its length constraint),
 * and a small mu perturbs the frictionless solution by a small deficit, with no
 * cancellation.
 */
#include <math.h>
#include <string.h>

#include "tendonrod.h"
#include "tr_internal.h"

/* Slots of the frictional tendons, and the counts of states and unknowns. */
static void layout(tr_model *m)
{
    int i;
    m->nfric = 0;
    for (i = 0; i < m->nt; i++) m->tendon[i].fric_index = m->tendon[i].mu > 0.0 ? m->nfric++ : -1;
    m->n_states = m->n_base + m->ndisp + m->nfric;
    m->n_states_rec = m->n_base + m->nt + 2 * m->nfric;
    m->n_unknowns = tr_n_force(m) + m->ndisp + (m->nshoot - 1) * m->n_states;
    m->rhs_work = tr_rhs_work(m);
}

int tr_model_set_friction(tr_model *m, const double *mu, const int *sliding, char *msg,
                          size_t msglen)
{
    int i, any = 0;
    if (msg && msglen) msg[0] = '\0';
    if (!m || (m->nt > 0 && (!mu || !sliding))) {
        tr_msgf(msg, msglen, "invalid arguments to tr_model_set_friction (NULL array)");
        return TR_EINVAL;
    }
    for (i = 0; i < m->nt; i++) {
        if (!(mu[i] >= 0.0) || !isfinite(mu[i])) {
            tr_msgf(msg, msglen, "friction of tendon %d = %g must be finite and >= 0", i, mu[i]);
            return TR_EINVAL;
        }
        if (sliding[i] != 1 && sliding[i] != -1) {
            tr_msgf(msg, msglen, "sliding of tendon %d = %d must be +1 (in) or -1 (out)", i,
                    sliding[i]);
            return TR_EINVAL;
        }
        any |= mu[i] > 0.0;
    }
    if (!any && m->nfric == 0) return TR_OK; /* the frictionless model, exactly as compiled */
    for (i = 0; i < m->nt; i++) {
        m->tendon[i].mu = mu[i];
        m->tendon[i].slide = sliding[i];
    }
    layout(m);
    return TR_OK;
}

void tr_friction_copy(tr_model *dst, const tr_model *src)
{
    int i;
    for (i = 0; i < src->nt; i++) {
        dst->tendon[i].mu = src->tendon[i].mu;
        dst->tendon[i].slide = src->tendon[i].slide;
    }
    layout(dst);
}

const double *tr_tensions_at(const tr_model *m_, const tr_data *d, const double *y)
{
    const tr_model *m = TR_IN(m_, d);
    int i;
    if (m->nfric == 0) return d->tau;
    for (i = 0; i < m->nt; i++) d->tau_here[i] = tr_tension_at(m, d, i, y);
    return d->tau_here;
}

double tr_friction_exponent(const tr_model *m)
{
    double g = 0.0;
    int i;
    for (i = 0; i < m->nt; i++) {
        const tr_tendon *t = &m->tendon[i];
        const double r = fmax(fabs(t->b), fabs(t->b + t->a * t->t));
        double th;
        if (t->fric_index < 0 || !(r > 0.0)) continue;
        th = t->control == TR_DISPLACEMENT ? fabs(t->value) / r : fabs(t->value) * r * t->t / m->EI;
        if (isfinite(th)) g += t->mu * th;
    }
    return g;
}
