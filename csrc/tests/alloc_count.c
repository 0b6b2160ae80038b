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
#include "tr_actuate.h"
#include "tr_path.h"

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

/* The model of family f (friction aside), its TR_ALLOC_ALL workspace (with accept_unstable
 * as `unjudged` says: an actuation's iterates are not judged, a path's points are) and a
 * cold solve; NULL on failure. */
static tr_data *prepare(const struct family *f, int unjudged, tr_model **mp)
{
    double rod[6], loads[7] = {0}, dist[3] = {0, 0, 0}, td[NT_MAX * TR_TD_NCOL];
    char msg[TR_MSGLEN];
    int i;
    tr_options o = tr_default_options();
    tr_data *d;
    rod[TR_ROD_L] = f->L, rod[TR_ROD_EI] = f->EI, rod[TR_ROD_GJ] = f->EI / 1.3;
    rod[TR_ROD_EA] = 1e4 * f->EI / (f->L * f->L) * 1e3, rod[TR_ROD_GA] = rod[TR_ROD_EA] / 2.6;
    rod[TR_ROD_KIRCHHOFF] = f->kirchhoff;
    loads[TR_LD_S] = f->L;
    for (i = 0; i < 3; i++) loads[TR_LD_F + i] = f->F[i], loads[TR_LD_M + i] = f->M[i];
    for (i = 0; i < f->nt; i++) memcpy(td + i * TR_TD_NCOL, f->tendon[i], sizeof f->tendon[i]);
    o.shooting_segments = f->segments;
    o.auto_shooting = f->auto_shooting;
    o.accept_unstable = unjudged;
    *mp = NULL;
    if (tr_model_alloc(mp, rod, td, f->nt, loads, 1, dist, &o, msg, sizeof msg) != TR_OK ||
        !(d = tr_data_alloc_ext(*mp, &o, 21, NULL, TR_ALLOC_ALL, msg, sizeof msg))) {
        fprintf(stderr, "%s: %s\n", f->name, msg);
        tr_model_free(*mp);
        return NULL;
    }
    if (tr_solve(*mp, d, NULL, NULL) < 0) {
        fprintf(stderr, "%s: the scene did not solve: %s\n", f->name, tr_data_message(d));
        tr_data_free(d);
        tr_model_free(*mp);
        return NULL;
    }
    return d;
}

/* One tr_path (tendon 0's value from its scene value to 1.2 times it) on family f's
 * workspace, counted: n[0] core, n[1] GSL allocations; its status. */
static int count_path(const struct family *f, long n[2])
{
    enum { CAP = 64 };
    static double par[CAP], tip[CAP * 18], ten[CAP * NT_MAX], margin[CAP], tl[CAP], x[CAP * 64],
        res[CAP], trunc[CAP];
    static int stable[CAP], kind[CAP], branch[CAP], steps[CAP];
    tr_model *m;
    tr_data *d = prepare(f, 0, &m);
    tr_path_spec sp;
    tr_path_out o;
    int st;
    if (!d) return -1000;
    memset(&sp, 0, sizeof sp);
    sp.kind = TR_PATH_SLOT, sp.index = 0;
    sp.p0 = f->tendon[0][TR_TD_VALUE], sp.p1 = 1.2 * sp.p0;
    sp.ds0 = 0.05, sp.ds_max = 0.2;
    o.cap = CAP, o.n = 0, o.par = par, o.tip = tip, o.tension = ten, o.margin = margin;
    o.stable = stable, o.kind = kind, o.branch = branch, o.tlam = tl, o.x = x, o.steps = steps;
    o.residual = res, o.truncation = trunc;
    allocations[0] = allocations[1] = 0;
    counting = 1;
    st = tr_path(m, d, &sp, &o);
    counting = 0;
    n[0] = allocations[0], n[1] = allocations[1];
    tr_data_free(d);
    tr_model_free(m);
    return st;
}

/* The tip of family f solved with tendon 0's control 20 % larger (an actuation's target). */
static int target_tip(const struct family *f, double tip[12], double *angle)
{
    tr_model *m;
    tr_data *d = prepare(f, 1, &m);
    double v[NT_MAX];
    char msg[TR_MSGLEN];
    tr_outputs out;
    int i, st;
    if (!d) return -1000;
    for (i = 0; i < f->nt; i++) v[i] = (i ? 1.0 : 1.2) * f->tendon[i][TR_TD_VALUE];
    st = tr_data_set_values(m, d, v, NULL, NULL, msg, sizeof msg);
    if (st == TR_OK) st = tr_solve(m, d, NULL, NULL);
    tr_data_outputs(d, &out);
    memcpy(tip, out.tip, 12 * sizeof(double));
    *angle = out.tip_angle;
    tr_data_free(d);
    tr_model_free(m);
    return st;
}

/* One tr_actuate of kind `kind` with controls tendons 0..nc-1 toward target goal (rows:
 * of a position, m of them; 6 with a rotation: a pose) on family f's workspace, counted:
 * n[0] core, n[1] GSL allocations; its final solve's status, or -100 - its outcome when
 * it did not reach the target (every target here is reachable exactly). */
static int count_actuate(const struct family *f, int kind, int nc, int goal, int mt, long n[2])
{
    const double r = f->tendon[0][TR_TD_OFFSET], tau = f->EI / (r * f->L);
    double tip[12], angle, c0[NT_MAX], scale[NT_MAX], values[NT_MAX], floor0[NT_MAX];
    double c[NT_MAX], mus[NT_MAX], floors[NT_MAX];
    int idx[NT_MAX], i, st;
    tr_model *m;
    tr_data *d;
    tr_act_spec sp;
    tr_act_result res;
    tr_act_target *tg = &sp.target;
    if (target_tip(f, tip, &angle) < 0 || !(d = prepare(f, 1, &m))) return -1000;
    memset(&sp, 0, sizeof sp);
    memset(&res, 0, sizeof res);
    for (i = 0; i < f->nt; i++) {
        idx[i] = i, c0[i] = values[i] = f->tendon[i][TR_TD_VALUE], scale[i] = r;
        floor0[i] = kind == TR_ACT_MIN_CHANGE ? 0.0 : -INFINITY;
    }
    sp.kind = kind, sp.n = nc, sp.idx = idx, sp.c0 = c0, sp.scale = scale, sp.values = values;
    sp.floor0 = floor0, sp.tau_scale = tau, sp.k = tau / r, sp.tol = 1e-8, sp.max_iter = 20;
    sp.tip_row = m->nseg;
    tg->goal = goal, tg->m = mt, tg->L = f->L;
    if (goal == TR_TARGET_ANGLE) {
        tg->theta = angle;
    } else if (goal == TR_TARGET_DIRECTION) { /* the tip tangent, a basis normal to it */
        const double t[3] = {tip[5], tip[8], tip[11]};
        const double a[3] = {fabs(t[0]) < 0.9 ? 1.0 : 0.0, fabs(t[0]) < 0.9 ? 0.0 : 1.0, 0.0};
        double b1[3], b2[3], nb;
        b1[0] = a[1] * t[2] - a[2] * t[1], b1[1] = a[2] * t[0] - a[0] * t[2];
        b1[2] = a[0] * t[1] - a[1] * t[0];
        nb = sqrt(b1[0] * b1[0] + b1[1] * b1[1] + b1[2] * b1[2]);
        for (i = 0; i < 3; i++) b1[i] /= nb;
        b2[0] = t[1] * b1[2] - t[2] * b1[1], b2[1] = t[2] * b1[0] - t[0] * b1[2];
        b2[2] = t[0] * b1[1] - t[1] * b1[0];
        memcpy(tg->t, t, sizeof t);
        memcpy(tg->BT, b1, sizeof b1);
        memcpy(tg->BT + 3, b2, sizeof b2);
    } else {
        memcpy(tg->p, tip, 3 * sizeof(double));
        memcpy(tg->R, tip + 3, 9 * sizeof(double));
        tg->has_R = mt == 6;
        for (i = 0; i < mt; i++) tg->rows[i] = i;
    }
    res.c = c, res.mus = mus, res.floors = floors;
    allocations[0] = allocations[1] = 0;
    counting = 1;
    st = tr_actuate(m, d, &sp, &res);
    counting = 0;
    n[0] = allocations[0], n[1] = allocations[1];
    /* the target is reachable exactly: a run that does not reach it is a failure here */
    if (st == TR_OK) st = res.success ? res.status : -100 - res.outcome;
    tr_data_free(d);
    tr_model_free(m);
    return st;
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
    /* the calls over the driver on the same workspaces: a path in a tendon's value, and an
     * actuation toward each target kind (the tip solved at another control) */
    printf("\n%-22s %5s %5s %3s\n", "call", "core", "GSL", "st");
    {
        const struct {
            const char *name;
            int fam, kind, nc, goal, mt; /* kind -1: a path */
        } call[] = {
            {"path_planar", 2, -1, 0, 0, 0},
            {"path_spatial", 3, -1, 0, 0, 0},
            {"actuate_angle", 2, TR_ACT_SQUARE, 1, TR_TARGET_ANGLE, 1},
            {"actuate_direction", 3, TR_ACT_SQUARE, 2, TR_TARGET_DIRECTION, 2},
            {"actuate_position", 3, TR_ACT_MIN_CHANGE, 3, TR_TARGET_POSITION, 2},
            /* a pose by two of the three symmetric tendons: with all three the controls'
             * common mode (every tendon retracted alike) only raises the tensions on the
             * inextensible backbone and leaves the tip where it is, so the reachable
             * controls are a line and the least-squares steps creep along it */
            {"actuate_pose", 3, TR_ACT_LEAST_SQUARES, 2, TR_TARGET_POSITION, 6},
        };
        for (i = 0; i < (int)(sizeof call / sizeof call[0]); i++) {
            long count[2] = {-1, -1};
            const struct family *f = &fam[call[i].fam];
            const int st = call[i].kind < 0 ? count_path(f, count)
                                            : count_actuate(f, call[i].kind, call[i].nc,
                                                            call[i].goal, call[i].mt, count);
            if (st == -1000) return 1;
            printf("%-22s %5ld %5ld %3d\n", call[i].name, count[0], count[1], st);
        }
    }
    return 0;
}
