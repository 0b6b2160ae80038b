/*
 * tr_confirm.c -- is an equilibrium found off the load path the answer?
 *
 * When load continuation from the unloaded robot stalls and a direct cold solve then
 * converges (TR_OFFPATH), that equilibrium may not be the one the loading reaches:
 * single shooting amplifies errors like exp(2 L sqrt(T/EI)) under tension and can land
 * on a looped rod.  A cold solve with another shooting formulation (8 segments, or
 * twice the number used) has basins of its own; only when both reach the same
 * equilibrium is it reported as a success (TR_CONFIRMED).
 *
 * A stage of the driver (tr_solve.c, solve_confirm), which runs the second solve itself:
 * tr_confirm_begin notes the equilibrium and sets the second formulation up,
 * tr_confirm_judge compares the two.  The second formulation is compiled and its
 * workspace allocated with the workspace (tr_data_alloc_confirm) and freed with it; this
 * workspace's inputs are copied into its inputs before each use.
 */
#include <math.h>
#include <string.h>

#include "tendonrod.h"
#include "tr_internal.h"

/* The confirming model and workspace, synchronised with m; 0, or -1 (message set). */
static int confirm_workspace(const tr_model *m, tr_data *d, int nshoot, const char *first)
{
    char msg[TR_MSGLEN];
    /* allocated with the workspace when continuation is on; here otherwise */
    if (!d->confirm_d && tr_data_alloc_confirm(m, d, msg, sizeof msg) != 0) {
        tr_data_free(d->confirm_d);
        tr_model_free(d->confirm_m);
        d->confirm_d = NULL;
        d->confirm_m = NULL;
        tr_set_message(d, "%s; not confirmed: the second formulation could not be set up (%s)",
                       first, msg);
        return -1;
    }
    if (!d->confirm_d || d->confirm_m->nshoot != nshoot) {
        tr_set_message(d, "%s; not confirmed: no second formulation of %d segments", first, nshoot);
        return -1;
    }
    tr_inputs_copy(d->confirm_d, m);
    tr_set_poll(d->confirm_d, d->poll, d->poll_ctx);
    /* the confirmation spends at most half of what is left of this solve's budget (the
     * stages after it need some) */
    d->confirm_d->opt.max_work =
        tr_work_budget(d) - d->spent > 2.0 ? 0.5 * (tr_work_budget(d) - d->spent) : 1.0;
    d->confirm_d->opt.max_time = d->opt.max_time;
    return 0;
}

int tr_confirm_begin(const tr_model *m_, tr_data *d, tr_confirm *c)
{
    const tr_model *m = TR_IN(m_, d);
    const int M = m->nshoot;
    double nw[3], mw[3];
    c->segments = M >= TR_CONFIRM_SEGMENTS ? 2 * M : TR_CONFIRM_SEGMENTS;
    memcpy(c->first, d->message, TR_MSGLEN);
    if (c->segments > TR_MAX_SHOOTING_SEGMENTS) {
        tr_set_message(d, "%s; not confirmed: no finer shooting formulation than %d segments",
                       c->first, M);
        return TR_OFFPATH;
    }
    /* the tip and tensions of this equilibrium */
    if (tr_residual(m, d, d->x, d->ft) != TR_OK) return d->stop ? d->stop : TR_OFFPATH;
    tr_state_world(m, d->y, c->tip, c->tip + 3, nw, mw);
    if (confirm_workspace(m, d, c->segments, c->first) != 0) return TR_OFFPATH;
    return TR_CONTINUE;
}

int tr_confirm_judge(const tr_model *m_, tr_data *d, const tr_confirm *c, int st)
{
    const tr_model *m = TR_IN(m_, d);
    const tr_data *cd = d->confirm_d;
    const int M2 = c->segments;
    double dtip = 0.0, dten = 0.0, tmax = 0.0;
    int i;
    d->nfev_confirm += cd->nfev;
    d->spent += cd->spent;
    if (st == TR_EINTERRUPTED) return d->stop = TR_EINTERRUPTED;
    /* an equilibrium of the confirming formulation, even one it found off the load path
     * itself, counts: the question is whether the two formulations agree */
    if (st < 0) {
        tr_set_message(d,
                       "%s; not confirmed: a cold solve with %d shooting segments did not "
                       "converge (%s)",
                       c->first, M2, tr_strerror(st));
        return TR_OFFPATH;
    }
    for (i = 0; i < 3; i++) {
        const double e = fabs(c->tip[i] - cd->pos[i]);
        if (!(e <= dtip)) dtip = e;
    }
    for (i = 0; i < m->nt; i++) {
        const double e = fabs(d->tau[i] - cd->tension[i]);
        if (!(e <= dten)) dten = e;
        if (fabs(d->tau[i]) > tmax) tmax = fabs(d->tau[i]);
    }
    if (dtip <= TR_CONFIRM_AGREE * m->L &&
        dten <= TR_CONFIRM_AGREE * (tmax > 0.0 ? tmax : 1e-300)) {
        tr_set_message(d,
                       "%s; confirmed: a cold solve with %d shooting segments reaches the same "
                       "equilibrium (tips %.1e L apart)",
                       c->first, M2, dtip / m->L);
        return TR_CONFIRMED;
    }
    tr_set_message(d,
                   "%s; not confirmed: a cold solve with %d shooting segments reaches a "
                   "different equilibrium (tips %.2g L apart), so this one is not reported as "
                   "the answer",
                   c->first, M2, dtip / m->L);
    return TR_OFFPATH;
}
