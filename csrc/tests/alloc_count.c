/* Allocations during solves: a scene of each stress family is compiled and given its
 * workspace (tr_data_alloc_ext with TR_ALLOC_ALL: everything a solve can need), then
 * solved cold, warm and cold again while every malloc, calloc and realloc of the process is counted (this file interposes them), by who asked:
 * the core or a shared library (GSL).  Prints one line per family: the allocations of the
 * first solve (core, GSL), of the next two (core, GSL), the first one's status; exits 0.
 * glibc only (__libc_*, dladdr); under valgrind, whose allocator takes the place of
 * these, it counts nothing.  Build from the repository root:
 *   cc -std=gnu99 -O2 -Icsrc csrc/tests/alloc_count.c csrc/tr_*.c \
 *      $(pkg-config --cflags --libs gsl) -lm -o /tmp/alloc_count */
#define _GNU_SOURCE /* dladdr */
#include <dlfcn.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <gsl/gsl_errno.h>

#include "tendonrod.h"

extern void *__libc_malloc(size_t);
extern void *__libc_calloc(size_t, size_t);
extern void *__libc_realloc(void *, size_t);
extern void __libc_free(void *);

static int counting;
static long allocations[2]; /* by the core (this executable), by a shared library (GSL) */

/* Count an allocation by where it was called from. */
static void count(const void *caller)
{
    Dl_info in, self;
    if (!counting) return;
    allocations[dladdr(caller, &in) && dladdr((void *)count, &self) &&
                in.dli_fbase != self.dli_fbase]++;
}

void *malloc(size_t n)
{
    count(__builtin_return_address(0));
    return __libc_malloc(n);
}

void *calloc(size_t a, size_t b)
{
    count(__builtin_return_address(0));
    return __libc_calloc(a, b);
}

void *realloc(void *p, size_t n)
{
    count(__builtin_return_address(0));
    return __libc_realloc(p, n);
}

void free(void *p)
{
    __libc_free(p);
}

enum { NT_MAX = 4 };

struct family {
    const char *name;
    double L, EI, kirchhoff;
    int nt;
    double tendon[NT_MAX][TR_TD_NCOL];
    double F[3], M[3]; /* tip load [N], [N m] */
    double mu;         /* friction of every tendon */
    int segments, auto_shooting;
};

static void tendon(double *t, double r, double angle, double EA, int control, double value)
{
    t[TR_TD_OFFSET] = r, t[TR_TD_ANGLE] = angle, t[TR_TD_SLOPE] = 0.0, t[TR_TD_EA] = EA;
    t[TR_TD_END] = 0.2, t[TR_TD_CONTROL] = control, t[TR_TD_VALUE] = value;
    t[TR_TD_PRETENSION] = 0.0;
}

/* Cold, then warm (the loads 1 % larger) and cold again: n[0], n[1] the allocations of the
 * first solve by the core and by GSL, n[2], n[3] those of the next two; the status of the
 * first. */
static int run(const struct family *f, long n[4])
{
    double rod[6], loads[7] = {0}, dist[3] = {0, 0, 0}, td[NT_MAX * TR_TD_NCOL], mu[NT_MAX];
    int sliding[NT_MAX], i, st, st0;
    char msg[TR_MSGLEN];
    tr_options o = tr_default_options();
    tr_model *m = NULL;
    tr_data *d;
    rod[TR_ROD_L] = f->L, rod[TR_ROD_EI] = f->EI, rod[TR_ROD_GJ] = f->EI / 1.3;
    rod[TR_ROD_EA] = 1e4 * f->EI / (f->L * f->L) * 1e3, rod[TR_ROD_GA] = rod[TR_ROD_EA] / 2.6;
    rod[TR_ROD_KIRCHHOFF] = f->kirchhoff;
    loads[TR_LD_S] = f->L;
    for (i = 0; i < 3; i++) loads[TR_LD_F + i] = f->F[i], loads[TR_LD_M + i] = f->M[i];
    for (i = 0; i < f->nt; i++) {
        memcpy(td + i * TR_TD_NCOL, f->tendon[i], sizeof f->tendon[i]);
        mu[i] = f->mu, sliding[i] = 1;
    }
    o.shooting_segments = f->segments;
    o.auto_shooting = f->auto_shooting;
    if (tr_model_alloc(&m, rod, td, f->nt, loads, 1, dist, &o, msg, sizeof msg) != TR_OK) {
        fprintf(stderr, "%s: model: %s\n", f->name, msg);
        return -1000;
    }
    if (f->mu > 0.0 && tr_model_set_friction(m, mu, sliding, msg, sizeof msg) != TR_OK) {
        fprintf(stderr, "%s: friction: %s\n", f->name, msg);
        return -1000;
    }
    d = tr_data_alloc_ext(m, &o, 21, NULL, TR_ALLOC_ALL, msg, sizeof msg);
    if (!d) {
        fprintf(stderr, "%s: data: %s\n", f->name, msg);
        return -1000;
    }
    allocations[0] = allocations[1] = 0;
    counting = 1;
    st0 = tr_solve(m, d, NULL, NULL);
    counting = 0;
    n[0] = allocations[0], n[1] = allocations[1];
    allocations[0] = allocations[1] = 0;
    {
        double value[NT_MAX], load[6];
        for (i = 0; i < f->nt; i++) value[i] = 1.01 * f->tendon[i][TR_TD_VALUE];
        for (i = 0; i < 3; i++) load[i] = 1.01 * f->F[i], load[3 + i] = 1.01 * f->M[i];
        if (tr_data_set_values(m, d, f->nt ? value : NULL, load, NULL, msg, sizeof msg) != TR_OK) {
            fprintf(stderr, "%s: values: %s\n", f->name, msg);
            return -1000;
        }
    }
    counting = 1;
    st = tr_solve_warm(m, d);
    st = tr_solve(m, d, NULL, NULL);
    counting = 0;
    (void)st;
    n[2] = allocations[0], n[3] = allocations[1];
    tr_data_free(d);
    tr_model_free(m);
    return st0;
}

int main(void)
{
    const double pi = 3.14159265358979323846, L = 0.2, EI = 207e9 * pi * pow(0.8e-3, 4) / 64;
    const double r = 0.01, q90 = r * pi / 2, F1 = EI / (L * L);
    struct family fam[10];
    int n = 0, i;
    gsl_set_error_handler_off();
    memset(fam, 0, sizeof fam);
    printf("%-22s %5s %5s %5s %5s %3s\n", "family", "core", "GSL", "core", "GSL", "st");
    for (i = 0; i < 10; i++)
        fam[i].L = L, fam[i].EI = EI, fam[i].kirchhoff = 1, fam[i].segments = 1,
        fam[i].auto_shooting = 1;
    fam[n].name = "plain_tip_force", fam[n].F[0] = F1, n++;
    fam[n].name = "plain_large_load", fam[n].F[0] = 30 * F1, n++;
    fam[n].name = "planar_tendon", fam[n].nt = 1, fam[n].F[0] = -0.2;
    tendon(fam[n].tendon[0], r, 0.0, INFINITY, TR_DISPLACEMENT, q90), n++;
    fam[n].name = "spatial_three_tendons", fam[n].nt = 3, fam[n].F[1] = 0.5;
    for (i = 0; i < 3; i++)
        tendon(fam[n].tendon[i], r, 2 * pi * i / 3, 2e3, TR_DISPLACEMENT, 0.002);
    n++;
    fam[n].name = "slack", fam[n].nt = 1, fam[n].F[2] = -0.5;
    tendon(fam[n].tendon[0], r, 0.0, INFINITY, TR_DISPLACEMENT, q90), n++;
    fam[n].name = "offpath_confirmed", fam[n].F[2] = 400 * F1, fam[n].auto_shooting = 0, n++;
    fam[n].name = "column_buckled", fam[n].F[0] = 1e-3 * F1, fam[n].F[2] = -1.5 * pi * pi / 4 * F1,
    n++;
    fam[n].name = "friction", fam[n].nt = 1, fam[n].mu = 0.3, fam[n].F[0] = 0.1;
    tendon(fam[n].tendon[0], r, 0.0, 3e3, TR_DISPLACEMENT, 0.01), n++;
    fam[n].name = "multiple_shooting", fam[n].F[0] = F1, fam[n].F[2] = 100 * F1,
    fam[n].segments = 4, n++;
    fam[n].name = "cosserat_tension", fam[n].kirchhoff = 0, fam[n].nt = 1, fam[n].F[1] = 0.1;
    tendon(fam[n].tendon[0], r, pi / 2, INFINITY, TR_TENSION, 2.0), n++;
    for (i = 0; i < n; i++) {
        long count[4] = {-1, -1, -1, -1};
        const int st = run(&fam[i], count);
        if (st == -1000) return 1;
        printf("%-22s %5ld %5ld %5ld %5ld %3d\n", fam[i].name, count[0], count[1], count[2],
               count[3], st);
    }
    return 0;
}
