/* Threads sharing one compiled model: each model of a few scene families is compiled
 * once; a sequence of calls -- set the workspace's values, a warm solve, a linearisation
 * in a design parameter (the rod's EI, a tendon's EA: the perturbations that used to need
 * a copy of the model) -- runs first in series, then on NTHREAD threads at once, each with
 * its own workspace and the one model.  Every thread's outputs (status, evaluations, tip
 * state, tensions, the linearisation) must be bitwise those of the series run: the model
 * is only read, and nothing else is shared.  Prints "ok", the solves that succeeded and
 * the linearisations that did (exit 0), or what differed.
 * Build from the repository root:
 *   cc -std=gnu99 -O2 -pthread -Icsrc csrc/tests/threads_one_model.c csrc/tr_*.c \
 *      $(pkg-config --cflags --libs gsl) -lm -o /tmp/threads_one_model */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <gsl/gsl_errno.h>

#include "tendonrod.h"
#include "tr_internal.h" /* reads the workspace's fields */

enum { NTHREAD = 4, NSTEP = 5, NT_MAX = 3, NOUT = 2 + 18 + NT_MAX + 6 * 2 };

struct family {
    const char *name;
    int nt, kirchhoff, segments, auto_shooting;
    double tendon[NT_MAX][TR_TD_NCOL];
    double F[3]; /* tip force at the first step [N] */
    double mu;   /* friction of every tendon (0: none) */
    double grow; /* the tendons' values and the load grow by this factor per step */
    tr_model *m;
    double out[NSTEP][NOUT]; /* the series run's outputs */
};

struct job {
    struct family *f;
    double out[NSTEP][NOUT];
    int failed;
};

static void tendon(double *t, double r, double angle, double EA, int control, double value)
{
    t[TR_TD_OFFSET] = r, t[TR_TD_ANGLE] = angle, t[TR_TD_SLOPE] = 0.0, t[TR_TD_EA] = EA;
    t[TR_TD_END] = 0.2, t[TR_TD_CONTROL] = control, t[TR_TD_VALUE] = value;
    t[TR_TD_PRETENSION] = 0.0;
}

static int compile(struct family *f)
{
    const double pi = 3.14159265358979323846, L = 0.2, EI = 207e9 * pi * pow(0.8e-3, 4) / 64;
    double rod[6], loads[7] = {0}, dist[3] = {0, 0, 0}, td[NT_MAX * TR_TD_NCOL], mu[NT_MAX];
    int sliding[NT_MAX], i;
    char msg[TR_MSGLEN];
    tr_options o = tr_default_options();
    rod[TR_ROD_L] = L, rod[TR_ROD_EI] = EI, rod[TR_ROD_GJ] = EI / 1.3;
    rod[TR_ROD_EA] = 1e7 * EI / (L * L), rod[TR_ROD_GA] = rod[TR_ROD_EA] / 2.6;
    rod[TR_ROD_KIRCHHOFF] = f->kirchhoff;
    loads[TR_LD_S] = L;
    for (i = 0; i < 3; i++) loads[TR_LD_F + i] = f->F[i];
    for (i = 0; i < f->nt; i++) {
        memcpy(td + i * TR_TD_NCOL, f->tendon[i], sizeof f->tendon[i]);
        mu[i] = f->mu, sliding[i] = 1;
    }
    o.shooting_segments = f->segments;
    o.auto_shooting = f->auto_shooting;
    o.force_spatial = 1; /* the linearisation's design parameters need no more */
    if (tr_model_alloc(&f->m, rod, td, f->nt, loads, 1, dist, &o, msg, sizeof msg) != TR_OK ||
        (f->mu > 0.0 && tr_model_set_friction(f->m, mu, sliding, msg, sizeof msg) != TR_OK)) {
        fprintf(stderr, "%s: model: %s\n", f->name, msg);
        return -1;
    }
    return 0;
}

/* The sequence of calls on a workspace of its own; outputs into out. */
static int run(const struct family *f, double out[NSTEP][NOUT])
{
    const tr_model *m = f->m;
    char msg[TR_MSGLEN];
    tr_options o = tr_default_options();
    tr_data *d;
    int s, i;
    o.force_spatial = 1;
    o.shooting_segments = f->segments;
    o.auto_shooting = f->auto_shooting;
    o.tip_only = 1;
    d = tr_data_alloc(m, &o, 1, NULL, msg, sizeof msg);
    if (!d) {
        fprintf(stderr, "%s: data: %s\n", f->name, msg);
        return -1;
    }
    memset(out, 0, sizeof(double) * NSTEP * NOUT);
    for (s = 0; s < NSTEP; s++) {
        const double g = pow(f->grow, s);
        double value[NT_MAX], load[6] = {0}, dpose[6 * 2];
        tr_param par[2];
        int np = 1, row = m->nseg, st;
        for (i = 0; i < f->nt; i++) value[i] = g * f->tendon[i][TR_TD_VALUE];
        for (i = 0; i < 3; i++) load[i] = g * f->F[i];
        if (tr_data_set_values(m, d, f->nt ? value : NULL, load, NULL, msg, sizeof msg) != TR_OK) {
            fprintf(stderr, "%s: values: %s\n", f->name, msg);
            tr_data_free(d);
            return -1;
        }
        st = tr_solve_warm(m, d);
        out[s][0] = st;
        out[s][1] = d->nfev;
        memcpy(out[s] + 2, d->tip, 18 * sizeof(double));
        memcpy(out[s] + 20, d->tau, (size_t)m->nt * sizeof(double));
        if (!TR_SUCCEEDED(st)) continue;
        par[0].kind = TR_PAR_ROD_EI, par[0].index = 0;
        if (f->nt > 0 && isfinite(f->tendon[0][TR_TD_EA]))
            par[1].kind = TR_PAR_TENDON_EA, par[1].index = 0, np = 2;
        st = tr_linearize(m, d, par, np, &row, 1, dpose, NULL, NULL, NULL, TR_DIFF_CENTRAL);
        if (st == TR_OK)
            memcpy(out[s] + 20 + NT_MAX, dpose, (size_t)6 * np * sizeof(double));
        else
            out[s][20 + NT_MAX] = 1000 + st;
    }
    tr_data_free(d);
    return 0;
}

static void *thread_main(void *arg)
{
    struct job *j = (struct job *)arg;
    j->failed = run(j->f, j->out) != 0;
    return NULL;
}

int main(void)
{
    const double pi = 3.14159265358979323846, r = 0.01;
    struct family fam[4];
    struct job jobs[NTHREAD];
    pthread_t th[NTHREAD];
    int n = 0, i, t, s, bad = 0, nsolved = 0, nlin = 0;
    gsl_set_error_handler_off();
    memset(fam, 0, sizeof fam);
    for (i = 0; i < 4; i++) fam[i].kirchhoff = 1, fam[i].segments = 1, fam[i].grow = 1.15;
    fam[n].name = "spatial_three_tendons", fam[n].nt = 3, fam[n].F[1] = 0.3;
    for (i = 0; i < 3; i++)
        tendon(fam[n].tendon[i], r, 2 * pi * i / 3, 2e3, TR_DISPLACEMENT, 0.002);
    n++;
    fam[n].name = "friction", fam[n].nt = 1, fam[n].mu = 0.3, fam[n].F[0] = 0.1;
    tendon(fam[n].tendon[0], r, 0.0, 3e3, TR_DISPLACEMENT, 0.01), n++;
    fam[n].name = "cosserat_tension", fam[n].kirchhoff = 0, fam[n].nt = 1, fam[n].F[1] = 0.1;
    tendon(fam[n].tendon[0], r, pi / 2, INFINITY, TR_TENSION, 2.0), n++;
    fam[n].name = "plain_multiple_shooting", fam[n].F[0] = 0.1, fam[n].F[2] = 10.0;
    fam[n].segments = 4, n++;
    for (i = 0; i < n; i++) {
        if (compile(&fam[i]) != 0 || run(&fam[i], fam[i].out) != 0) return 1;
        if (!TR_SUCCEEDED((int)fam[i].out[0][0])) {
            fprintf(stderr, "%s: the first solve failed (%g)\n", fam[i].name, fam[i].out[0][0]);
            return 1;
        }
        for (s = 0; s < NSTEP; s++) {
            nsolved += TR_SUCCEEDED((int)fam[i].out[s][0]);
            nlin += TR_SUCCEEDED((int)fam[i].out[s][0]) && fam[i].out[s][20 + NT_MAX] < 1000.0 &&
                    fam[i].out[s][20 + NT_MAX] != 0.0;
        }
        for (t = 0; t < NTHREAD; t++) {
            jobs[t].f = &fam[i];
            if (pthread_create(&th[t], NULL, thread_main, &jobs[t]) != 0) return 1;
        }
        for (t = 0; t < NTHREAD; t++) pthread_join(th[t], NULL);
        for (t = 0; t < NTHREAD; t++)
            if (jobs[t].failed || memcmp(jobs[t].out, fam[i].out, sizeof fam[i].out) != 0) {
                printf("%s: thread %d differs from the series run\n", fam[i].name, t);
                bad = 1;
            }
        tr_model_free(fam[i].m);
    }
    if (!bad) printf("ok %d solves %d linearisations of %d\n", nsolved, nlin, n * NSTEP);
    return bad;
}
