/*
 * solve_harness.c -- the bare C core on the scenes of bench/solve.py, with no Python in
 * the loop: the reference that the public API's per-call overhead is measured against.
 *
 * Reads from stdin (written by bench/solve.py) a scene and a sweep of K load sets:
 *   nt nl nodes K
 *   rod (6)
 *   tendons (nt x 8)
 *   K times: values (nt), loads (nl x 7), dist (3)   (set 0: the scene; set i: a step of
 *            1 % further along the sweep, see bench/solve.py)
 * and times, with the default options (automatic steps) and lazy outputs (tip, tensions,
 * slacks: what tr.solve computes before a node array is read), medians over `reps`
 * repetitions of:
 *   cold        compile the model and workspace of set 0, tr_solve from the cold guess,
 *               free (what tr.solve(scene) does in C);
 *   warm_guess  for each set i >= 1: compile, tr_solve_from the solution of set i - 1
 *               (its base state, Jacobian and verification record), free
 *               (tr.solve(scene_i, guess=sol_{i-1}));
 *   warm        one model and workspace; for each set i >= 1 the values set, then
 *               tr_solve_warm (Problem.solve along the sweep).
 * Prints one line of key=value pairs: times in microseconds per solve, and the mean nfev
 * of each kind.  Built with -DHARNESS_LIBRARY -shared -fPIC it is a library whose
 * harness_run_text bench/solve.py calls through ctypes, alternating with Python.
 *
 *   gcc -O2 -std=c99 -D_POSIX_C_SOURCE=200809L -Icsrc $(pkg-config --cflags gsl) \
 *       bench/solve_harness.c csrc/tr_*.c -o /tmp/solve_harness $(pkg-config --libs gsl) -lm
 *   /tmp/solve_harness [reps=31] < sweep.txt
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <gsl/gsl_errno.h>
#include "tendonrod.h"

#define MAXT 16
#define MAXL 16
#define MAXK 101
#define MAXR 1001
#define MAXU 128

typedef struct {
    int nt, nl, nodes, K;
    double rod[6], tendons[MAXT * 8], values[MAXK][MAXT], loads[MAXK][MAXL * 7], dist[MAXK][3];
} sweep;

/* What a solve hands to the next warm start from a guess (as a Solution does): its base
 * state, Jacobian, step verification and stability verdict record. */
typedef struct {
    double g[6 + 2 * MAXT], J[MAXU * MAXU], xv[MAXU],
        carry[5 + MAXU + MAXT + 7 * (MAXL + MAXT + 2) + 3];
    char reason[256];
    int have_carry;
    tr_verified ver;
} start;

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

static int cmp(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *t, int n)
{
    qsort(t, (size_t)n, sizeof *t, cmp);
    return t[n / 2];
}

static int read_doubles(FILE *in, double *v, int n)
{
    int i;
    for (i = 0; i < n; i++)
        if (fscanf(in, "%lf", v + i) != 1) return -1;
    return 0;
}

static int read_sweep(FILE *in, sweep *s)
{
    int i;
    if (fscanf(in, "%d %d %d %d", &s->nt, &s->nl, &s->nodes, &s->K) != 4 || s->nt < 0 ||
        s->nt > MAXT || s->nl < 0 || s->nl > MAXL || s->nodes < 1 || s->K < 2 || s->K > MAXK)
        return -1;
    if (read_doubles(in, s->rod, 6) || read_doubles(in, s->tendons, 8 * s->nt)) return -1;
    for (i = 0; i < s->K; i++)
        if (read_doubles(in, s->values[i], s->nt) || read_doubles(in, s->loads[i], 7 * s->nl) ||
            read_doubles(in, s->dist[i], 3))
            return -1;
    return 0;
}

static int compile(const sweep *s, int i, tr_model **m, tr_data **d)
{
    char msg[TR_MSGLEN];
    double ten[MAXT * 8];
    tr_options o = tr_default_options();
    int j;
    memcpy(ten, s->tendons, (size_t)(8 * s->nt) * sizeof(double));
    for (j = 0; j < s->nt; j++) ten[8 * j + 6] = s->values[i][j];
    if (tr_model_alloc(m, s->rod, ten, s->nt, s->loads[i], s->nl, s->dist[i], &o, msg,
                       sizeof msg)) {
        fprintf(stderr, "model: %s\n", msg);
        return -1;
    }
    *d = tr_data_alloc(*m, &o, s->nodes, NULL, msg, sizeof msg);
    if (!*d) {
        fprintf(stderr, "workspace: %s\n", msg);
        tr_model_free(*m);
        return -1;
    }
    tr_data_set_lazy(*d, 1);
    return 0;
}

static int nfev_of(const tr_data *d)
{
    tr_result r;
    tr_data_result(d, &r);
    return r.nfev;
}

static void keep(const tr_model *m, const tr_data *d, start *st)
{
    const size_t k = (size_t)m->n_unknowns;
    const char *reason = tr_data_carry_reason(d);
    tr_outputs o;
    tr_verified v;
    tr_data_outputs(d, &o);
    tr_data_verified(d, &v);
    tr_base_state(m, d, st->g);
    memcpy(st->J, o.J, k * k * sizeof(double));
    memcpy(st->xv, v.x, k * sizeof(double));
    st->ver.steps = v.steps;
    st->ver.estimate = v.estimate;
    st->ver.x = st->xv;
    st->have_carry = tr_carry_len(m, d) <= (int)(sizeof st->carry / sizeof st->carry[0]) &&
                     tr_carry_get(m, d, st->carry);
    snprintf(st->reason, sizeof st->reason, "%s", reason ? reason : "");
}

/* tr_solve_from the start p, with its verdict record as a Solution passes it. */
static int solve_from(const tr_model *m, tr_data *d, const start *p)
{
    if (p->have_carry) tr_carry_set(m, d, p->carry, tr_carry_len(m, d), p->reason);
    return tr_solve_from(m, d, p->g, p->J, p->ver.steps > 0 ? &p->ver : NULL);
}

static int fail(const char *what, const tr_data *d)
{
    fprintf(stderr, "%s: %s\n", what, tr_data_message(d));
    return 1;
}

/* The measurements of the header on the sweep read from `in`, `reps` repetitions:
 * out = {cold_us, warm_guess_us, warm_us, nfev_cold, nfev_warm_guess, nfev_warm}.
 * 0, or nonzero with a message on stderr.  Also called through ctypes (bench/solve.py,
 * harness_run_text) so that Python and C alternate within one process. */
int harness_run(FILE *in, int reps, double out[6])
{
    static sweep s;
    static start starts[MAXK];
    static double tc[MAXR], tg[MAXR], tw[MAXR];
    double lv[6 * MAXL];
    long nfev_c = 0, nfev_g = 0, nfev_w = 0;
    tr_model *m;
    tr_data *d;
    int r, i, j, st;
    gsl_set_error_handler_off();
    if (reps < 1 || reps > MAXR || read_sweep(in, &s) < 0) {
        fprintf(stderr, "solve_harness: reps out of range or a malformed sweep (see the header)\n");
        return 2;
    }
    /* the chain of solutions along the sweep: the guesses of warm_guess */
    for (i = 0; i < s.K; i++) {
        if (compile(&s, i, &m, &d) < 0) return 1;
        if (m->n_unknowns > MAXU) return fail("too many unknowns for this harness", d);
        st = i == 0 ? tr_solve(m, d, NULL, NULL) : solve_from(m, d, &starts[i - 1]);
        if (!TR_SUCCEEDED(st)) return fail("sweep", d);
        keep(m, d, &starts[i]);
        tr_data_free(d);
        tr_model_free(m);
    }
    for (r = 0; r < reps; r++) {
        double t0 = now();
        if (compile(&s, 0, &m, &d) < 0) return 1;
        st = tr_solve(m, d, NULL, NULL);
        nfev_c += nfev_of(d);
        if (!TR_SUCCEEDED(st)) return fail("cold", d);
        tr_data_free(d);
        tr_model_free(m);
        tc[r] = now() - t0;

        t0 = now();
        for (i = 1; i < s.K; i++) {
            const start *p = &starts[i - 1];
            if (compile(&s, i, &m, &d) < 0) return 1;
            st = solve_from(m, d, p);
            nfev_g += nfev_of(d);
            if (!TR_SUCCEEDED(st)) return fail("warm_guess", d);
            tr_data_free(d);
            tr_model_free(m);
        }
        tg[r] = (now() - t0) / (s.K - 1);

        /* a fresh Problem per repetition, solved at set 0 first (not timed) */
        if (compile(&s, 0, &m, &d) < 0) return 1;
        if (!TR_SUCCEEDED(tr_solve(m, d, NULL, NULL))) return fail("warm start", d);
        t0 = now();
        for (i = 1; i < s.K; i++) {
            char msg[TR_MSGLEN];
            for (j = 0; j < s.nl; j++)
                memcpy(lv + 6 * j, s.loads[i] + 7 * j + 1, 6 * sizeof(double));
            if (tr_data_set_values(m, d, s.values[i], lv, s.dist[i], msg, sizeof msg)) {
                fprintf(stderr, "set_values: %s\n", msg);
                return 1;
            }
            st = tr_solve_warm(m, d);
            nfev_w += nfev_of(d);
            if (!TR_SUCCEEDED(st)) return fail("warm", d);
        }
        tw[r] = (now() - t0) / (s.K - 1);
        tr_data_free(d);
        tr_model_free(m);
    }
    out[0] = 1e6 * median(tc, reps);
    out[1] = 1e6 * median(tg, reps);
    out[2] = 1e6 * median(tw, reps);
    out[3] = (double)nfev_c / reps;
    out[4] = (double)nfev_g / (reps * (s.K - 1.0));
    out[5] = (double)nfev_w / (reps * (s.K - 1.0));
    return 0;
}

/* harness_run on a sweep given as text. */
int harness_run_text(const char *text, int reps, double out[6])
{
    FILE *in = fmemopen((void *)text, strlen(text), "r");
    int r;
    if (!in) return 2;
    r = harness_run(in, reps, out);
    fclose(in);
    return r;
}

#ifndef HARNESS_LIBRARY
int main(int argc, char **argv)
{
    double out[6];
    const int r = harness_run(stdin, argc > 1 ? atoi(argv[1]) : 31, out);
    if (r) return r;
    printf("cold_us=%.3f warm_guess_us=%.3f warm_us=%.3f nfev_cold=%.2f nfev_warm_guess=%.2f "
           "nfev_warm=%.2f\n",
           out[0], out[1], out[2], out[3], out[4], out[5]);
    return 0;
}
#endif
