/*
 * tr_poll.c -- the work budget and the caller's poll hook.
 *
 * Every integration (and every 256 steps of a long one, every step of an adaptive
 * one) asks tr_poll whether to go on.  The work budget (right-hand-side evaluations
 * weighted by their cost, tr_model.rhs_work) is checked every time (deterministic); the wall clock is read and,
 * at most every TR_POLL_INTERVAL, the caller's hook is called (the Python glue checks
 * for Ctrl-C there).  Once a poll says stop, the answer sticks (d->stop) until the next
 * solve starts, so every loop of the solver unwinds at once.  The interval runs from the
 * hook's last call (or its installation), across solves: a caller's loop of solves each
 * shorter than the interval (a batch's lean solves, a sweep) still reaches the hook.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <time.h>

#include "tendonrod.h"
#include "tr_internal.h"

double tr_clock(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void tr_set_poll(tr_data *d, int (*poll)(void *ctx), void *ctx)
{
    d->poll = poll;
    d->poll_ctx = ctx;
    d->t_poll = tr_clock();
}

void tr_poll_start(tr_data *d)
{
    d->stop = TR_OK;
    d->finishing = 0;
    d->spent = 0.0;
    d->t_start = tr_clock(); /* the hook's interval (t_poll) runs on across solves */
}

int tr_poll(tr_data *d)
{
    double now;
    if (d->stop) return d->stop;
    /* the final outputs of a solve that ran out of budget are still computed (its
     * states are the last iterate's); only an interrupt stops them */
    if (!d->finishing && d->spent > tr_work_budget(d)) return d->stop = TR_EBUDGET;
    if (!d->poll && !(d->opt.max_time > 0.0)) return TR_OK;
    now = tr_clock();
    if (!d->finishing && d->opt.max_time > 0.0 && now - d->t_start > d->opt.max_time)
        return d->stop = TR_EBUDGET;
    if (d->poll && now - d->t_poll >= TR_POLL_INTERVAL) {
        d->t_poll = now;
        if (d->poll(d->poll_ctx)) return d->stop = TR_EINTERRUPTED;
    }
    return TR_OK;
}
