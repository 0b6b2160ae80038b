/*
 * fuzz_core.c -- libFuzzer harness for the C core's entry points (no Python).
 *
 * Built straight from the csrc/ sources with clang -fsanitize=fuzzer,address,undefined
 * (bench/fuzz/run.sh).  Each input is decoded into one of
 *   - a scene (rod, tendons, point loads, distributed load), options, output
 *     nodes, an optional guess and an optional Jacobian, run through
 *     tr_model_alloc -> tr_data_alloc -> tr_solve -> (tr_compliance) -> free;
 *   - a vector of doubles fed to every closed-form kernel of tr_closed.h.
 * Every double is drawn from a mix of "sensible" values near a typical design
 * (so the fuzzer reaches the solver's iterations, continuation and recording,
 * not only the validation) and hostile ones (NaN, +-inf, +-0, subnormals,
 * DBL_MAX, raw bit patterns).
 *
 * Besides what ASan/UBSan catch (invalid access, leaks -- LeakSanitizer is on
 * in a libFuzzer build -- integer overflow, bad shifts, misaligned loads ...),
 * the harness checks the core's contract and abort()s with a message when it
 * is broken, so libFuzzer saves the input as a crash:
 *   C1 status codes are the documented ones; tr_strerror names each;
 *   C2 a failed tr_model_alloc returns NULL and a message; a successful one a model;
 *   C3 messages are NUL-terminated inside their buffers;
 *   C4 a solve that reports success (status >= 0) has finite outputs, tensions
 *      and slacks >= 0, a scaled residual <= tol, and -- where the core picks
 *      the step count (automatic or adaptive) -- an orthonormal rotation at
 *      every node (no "success" that is a lie);
 *   C5 work is bounded by the options: nfev <= max_nfev + one Jacobian and
 *      one recording/verification allowance (TR_FUZZ_NFEV_SLACK below);
 *   C6 a compliance matrix reported OK is finite;
 *   C7 the closed-form kernels: NaN exactly outside their documented domain
 *      (for finite, moderate inputs inside it the result is finite).
 * Options are clamped to small caps (steps <= 256, max_nfev <= 4000,
 * max_iter <= 60, max_continuation <= 16, nodes <= 64) so that one input runs
 * in milliseconds; the clamps are part of the input (hostile values like
 * negative caps or INT_MAX steps are tried too, behind a selector byte).
 */
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>

#include "tendonrod.h"
#include "tr_internal.h" /* reads the workspace's fields */
#include "tr_closed.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* nfev allowance beyond max_nfev: the cap is checked before each Newton
 * trial and each finite-difference Jacobian, so one Jacobian (n_unknowns
 * evaluations, added at the check) and the step-count verification and
 * recording passes (a few evaluations) may complete after it. */
#define TR_FUZZ_NFEV_SLACK 16
#define TR_FUZZ_MAX_NT     6
#define TR_FUZZ_MAX_NL     4
#define TR_FUZZ_MAX_NODES  64

typedef struct {
    const uint8_t *p;
    size_t n;
} reader;

static unsigned u8(reader *r)
{
    if (r->n == 0) return 0;
    r->n--;
    return *r->p++;
}

static unsigned u16(reader *r)
{
    unsigned a = u8(r);
    return a | (u8(r) << 8);
}

static double raw_double(reader *r)
{
    uint8_t b[8];
    double x;
    for (int i = 0; i < 8; i++) b[i] = (uint8_t)u8(r);
    memcpy(&x, b, sizeof x);
    return x;
}

/* A value near `typical` most of the time, a hostile one otherwise. */
static double val(reader *r, double typical)
{
    const unsigned sel = u8(r);
    if (sel < 150) /* typical * [0.25, 4) on a log scale, either sign 1/16 */
        return (sel % 16 == 15 ? -typical : typical) * exp2((double)(sel % 150) / 37.5 - 2.0);
    switch (sel - 150) {
    case 0: return NAN;
    case 1: return INFINITY;
    case 2: return -INFINITY;
    case 3: return 0.0;
    case 4: return -0.0;
    case 5: return DBL_MIN;
    case 6: return 4.9406564584124654e-324;
    case 7: return DBL_MAX;
    case 8: return -DBL_MAX;
    case 9: return typical * 1e6;
    case 10: return typical * 1e-6;
    case 11: return typical * 1e12;
    case 12: return typical * 1e-12;
    case 13: return typical * 1e100;
    case 14: return typical * 1e-100;
    case 15: return 1.0;
    case 16: return -1.0;
    default: break;
    }
    if (sel < 240) /* typical times a small signed factor */
        return typical * ((double)(int)u8(r) - 128.0) / 16.0;
    return raw_double(r);
}

static int ival(reader *r, int lo, int hi)
{
    const unsigned sel = u8(r);
    switch (sel) {
    case 250: return -1;
    case 251: return 0;
    case 252: return INT_MAX;
    case 253: return INT_MIN;
    case 254: return hi * 1000;
    default: return lo + (int)(sel % (unsigned)(hi - lo + 1));
    }
}

static int verbose = 0; /* TR_FUZZ_VERBOSE=1: print each decoded case (for reproducers) */

static void print_case(const double rod[6], const double *tend, int nt, const double *loads, int nl,
                       const double dist[3], const tr_options *o, int nnode, int use_nodes)
{
    int i, j;
    fprintf(stderr, "rod = [%.17g, %.17g, %.17g, %.17g, %.17g, %.17g]\n", rod[0], rod[1], rod[2],
            rod[3], rod[4], rod[5]);
    for (i = 0; i < nt; i++) {
        fprintf(stderr, "tendon[%d] = [", i);
        for (j = 0; j < 8; j++) fprintf(stderr, "%.17g%s", tend[8 * i + j], j < 7 ? ", " : "]\n");
    }
    for (i = 0; i < nl; i++) {
        fprintf(stderr, "load[%d] = [", i);
        for (j = 0; j < 7; j++) fprintf(stderr, "%.17g%s", loads[7 * i + j], j < 6 ? ", " : "]\n");
    }
    fprintf(stderr, "dist = [%.17g, %.17g, %.17g]\n", dist[0], dist[1], dist[2]);
    fprintf(stderr,
            "options: integrator=%d steps=%d rtol=%.17g tol=%.17g max_iter=%d max_nfev=%d "
            "jacobian_method=%d slack_model=%d continuation=%d max_continuation=%d "
            "force_spatial=%d tip_only=%d shooting_segments=%d; nnode=%d explicit_nodes=%d\n",
            o->integrator, o->steps, o->rtol, o->tol, o->max_iter, o->max_nfev, o->jacobian_method,
            o->slack_model, o->continuation, o->max_continuation, o->force_spatial, o->tip_only,
            o->shooting_segments, nnode, use_nodes);
}

#define FAIL(...)                                                                                  \
    do {                                                                                           \
        fprintf(stderr, "fuzz_core contract violation: " __VA_ARGS__);                             \
        fprintf(stderr, "\n");                                                                     \
        abort();                                                                                   \
    } while (0)

static void check_msg(const char *msg, size_t len, const char *where)
{
    if (memchr(msg, '\0', len) == NULL) FAIL("C3 %s message not NUL-terminated", where);
}

/* a documented status: one that tr_strerror names (caveats > 0 are added as
 * the core grows, e.g. TR_OFFPATH = 3; TR_CONTINUE is internal) */
static int known_status(int st)
{
    const char *s = tr_strerror(st);
    return s != NULL && strstr(s, "unknown") == NULL && st != TR_CONTINUE;
}

static int finite_all(const double *x, int n)
{
    for (int i = 0; i < n; i++)
        if (!isfinite(x[i])) return 0;
    return 1;
}

/* ---------------------------------------------------------- closed forms */
static int moderate(double x)
{
    return x == 0.0 || (fabs(x) >= 1e-30 && fabs(x) <= 1e30);
}

static void fuzz_closed(reader *r)
{
    const double s = val(r, 0.1), F = val(r, 0.5), z = val(r, 0.15), L = val(r, 0.2);
    const double EI = val(r, 4e-3), a = val(r, -0.05), b = val(r, 0.01), k = val(r, 1e4);
    const double kb = val(r, 1e5), n = (double)ival(r, 0, 12), x = val(r, 0.5);
    const int beam = L > 0 && isfinite(L) && EI > 0 && isfinite(EI);
    const int dom_t = beam && z >= 0 && z <= L && k >= 0 && !isnan(F) && !isnan(a) && !isnan(b);
    const int dom_s = dom_t && s >= 0 && s <= L;
    const int all_mod = moderate(s) && moderate(F) && moderate(z) && moderate(L) && moderate(EI) &&
                        moderate(a) && moderate(b) && (moderate(k) || k == INFINITY);
    double v;

    v = tr_closed_tension(F, z, L, EI, a, b, k);
    if (!dom_t && !isnan(v)) FAIL("C7 tension not NaN outside the domain");
    if (dom_t && all_mod && !isfinite(v)) FAIL("C7 tension %g inside the domain", v);
    v = tr_closed_angle(s, F, z, L, EI, a, b, k);
    if (!dom_s && !isnan(v)) FAIL("C7 angle not NaN outside the domain");
    if (dom_s && all_mod && !isfinite(v)) FAIL("C7 angle %g inside the domain", v);
    v = tr_closed_deflection(s, F, z, L, EI, a, b, k);
    if (!dom_s && !isnan(v)) FAIL("C7 deflection not NaN outside the domain");
    if (dom_s && all_mod && !isfinite(v)) FAIL("C7 deflection %g inside the domain", v);
    v = tr_closed_equivalent_stiffness(k, kb);
    if (!(k >= 0 && kb >= 0) && !isnan(v)) FAIL("C7 equivalent_stiffness not NaN outside");
    if (k >= 0 && kb >= 0 && isnan(v))
        FAIL("C7 equivalent_stiffness NaN inside (k=%g kb=%g)", k, kb);
    v = tr_closed_pattern_factor(n);
    if ((n >= 1) != !isnan(v)) FAIL("C7 pattern_factor(%g) = %g", n, v);
    v = tr_closed_actuation_tension_for_angle(x, L, EI, a, b);
    if ((!beam || isnan(x)) && !isnan(v)) FAIL("C7 actuation angle not NaN outside");
    v = tr_closed_actuation_tension_for_deflection(x, L, EI, a, b);
    if ((!beam || isnan(x)) && !isnan(v)) FAIL("C7 actuation deflection not NaN outside");
}

/* ---------------------------------------------------------------- solver */
static void fuzz_solve(reader *r)
{
    double rod[6], tend[TR_FUZZ_MAX_NT * 8], loads[TR_FUZZ_MAX_NL * 7], dist[3];
    double guess[6 + 2 * TR_FUZZ_MAX_NT], jac[(6 + TR_FUZZ_MAX_NT) * (6 + TR_FUZZ_MAX_NT)];
    double node_s[TR_FUZZ_MAX_NODES], C[36];
    char msg[TR_MSGLEN];
    tr_model *m = NULL;
    tr_data *d = NULL;
    tr_options o = tr_default_options();
    const unsigned shape = u8(r), flags = u8(r);
    const int nt = (int)(shape % (TR_FUZZ_MAX_NT + 1));
    const int nl = (int)((shape / 8) % (TR_FUZZ_MAX_NL + 1));
    int st, nnode, use_nodes, i, j;
    const double L0 = 0.2, EI0 = 4.2e-3;

    /* options: small caps by default, hostile ones behind the selector */
    o.integrator = (int)(flags % 3);
    o.slack_model = (int)((flags / 3) % 2);
    o.jacobian_method = (int)((flags / 6) % 2);
    o.continuation = (int)((flags / 12) % 2);
    o.force_spatial = (int)((flags / 24) % 2);
    o.tip_only = (int)((flags / 48) % 2);
    o.steps = ival(r, 0, 64);
    o.max_iter = ival(r, 1, 60);
    o.max_nfev = ival(r, 1, 4000);
    o.max_continuation = ival(r, 0, 16);
    o.tol = val(r, 1e-10);
    o.rtol = val(r, 1e-8);
    o.shooting_segments = ival(r, 1, 8);
    if (o.shooting_segments > 16 || o.shooting_segments < 0)
        o.shooting_segments = o.shooting_segments < 0 ? o.shooting_segments : 16;
    if (u8(r) % 4 == 0) { /* keep the run short unless the input insists */
        if (o.steps > 256) o.steps = 256;
        if (o.max_nfev > 4000) o.max_nfev = 4000;
        if (o.max_iter > 60) o.max_iter = 60;
        if (o.max_continuation > 16) o.max_continuation = 16;
    } else {
        if (o.steps > 4096 || o.steps < 0) o.steps = o.steps < 0 ? o.steps : 4096;
        if (o.max_nfev > 20000) o.max_nfev = 20000;
        if (o.max_continuation > 64) o.max_continuation = 64;
        if (o.max_iter > 200) o.max_iter = 200;
    }
    /* adaptive: a positive rtol below 1e-14 makes every integration take
     * seconds (finding F14, known); keep such inputs out so that the run
     * explores the rest.  NaN, 0 and negative rtol stay: validation must
     * refuse them. */
    if (o.integrator == TR_ADAPTIVE && o.rtol > 0.0 && o.rtol < 1e-14) o.rtol = 1e-14;

    rod[0] = val(r, L0);
    rod[1] = val(r, EI0);
    rod[2] = val(r, 0.8 * EI0);
    rod[3] = val(r, 1e5);
    rod[4] = val(r, 4e4);
    {
        const unsigned kb = u8(r);
        rod[5] = kb < 120 ? 0.0 : kb < 240 ? 1.0 : val(r, 1.0);
    }
    for (i = 0; i < nt; i++) {
        double *t = tend + 8 * i;
        const unsigned kind = u8(r);
        t[0] = val(r, 0.01);
        t[1] = kind % 4 == 0   ? 0.0
               : kind % 4 == 1 ? M_PI
               : kind % 4 == 2 ? 2.0 * M_PI * i / (nt ? nt : 1)
                               : val(r, 1.0);
        t[2] = (kind / 4) % 3 == 0 ? 0.0 : (kind / 4) % 3 == 1 ? -t[0] / rod[0] : val(r, -0.02);
        t[3] = (kind / 12) % 2 == 0 ? INFINITY : val(r, 1e4);
        t[4] = (kind / 24) % 2 == 0 ? rod[0] : val(r, 0.1);
        t[5] = (kind / 48) % 4 == 3 ? val(r, 1.0) : (double)((kind / 48) % 2);
        t[6] = t[5] == 0.0 ? val(r, 0.005) : val(r, 1.0);
        t[7] = (kind / 192) % 2 == 0 ? 0.0 : val(r, 2.0);
    }
    for (i = 0; i < nl; i++) {
        double *l = loads + 7 * i;
        l[0] = u8(r) % 2 ? rod[0] : val(r, 0.1);
        for (j = 1; j < 4; j++) l[j] = u8(r) % 3 ? 0.0 : val(r, 0.5);
        for (j = 4; j < 7; j++) l[j] = u8(r) % 3 ? 0.0 : val(r, 0.01);
    }
    for (j = 0; j < 3; j++) dist[j] = u8(r) % 3 ? 0.0 : val(r, 0.5);

    if (verbose) print_case(rod, tend, nt, loads, nl, dist, &o, -1, -1);
    st = tr_model_alloc(&m, rod, nt ? tend : NULL, nt, nl ? loads : NULL, nl, dist, &o, msg,
                        sizeof msg);
    check_msg(msg, sizeof msg, "tr_model_alloc");
    if (!known_status(st)) FAIL("C1 tr_model_alloc returned %d", st);
    if (tr_strerror(st) == NULL) FAIL("C1 tr_strerror(%d) is NULL", st);
    if (st < 0) {
        if (m != NULL) FAIL("C2 tr_model_alloc failed (%d) but returned a model", st);
        if (msg[0] == '\0') FAIL("C2 tr_model_alloc failed (%d) without a message", st);
        return;
    }
    if (m == NULL) FAIL("C2 tr_model_alloc returned %d and no model", st);

    nnode = ival(r, 1, TR_FUZZ_MAX_NODES);
    use_nodes = (int)(u8(r) % 3 == 0);
    if (use_nodes) {
        if (nnode > TR_FUZZ_MAX_NODES || nnode < 0) nnode = TR_FUZZ_MAX_NODES;
        for (i = 0; i < nnode; i++)
            node_s[i] = u8(r) % 4 ? rod[0] * i / (nnode > 1 ? nnode - 1 : 1) : val(r, 0.1);
    } else if (nnode > 100000) {
        nnode = 100000; /* a huge count is a memory request, not a bug */
    }
    d = tr_data_alloc(m, &o, nnode, use_nodes ? node_s : NULL, msg, sizeof msg);
    check_msg(msg, sizeof msg, "tr_data_alloc");
    if (d == NULL) {
        if (msg[0] == '\0') FAIL("C2 tr_data_alloc failed without a message");
        tr_model_free(m);
        return;
    }
    {
        const unsigned g = u8(r);
        const int k = m->n_unknowns;
        const double *gp = NULL, *jp = NULL;
        if (g % 3 == 1) {
            for (i = 0; i < 6 + 2 * nt; i++) guess[i] = val(r, i < 3 ? 0.1 : i < 6 ? 0.01 : 1.0);
            gp = guess;
        }
        if (g / 3 % 3 == 1 && k <= 6 + TR_FUZZ_MAX_NT) {
            for (i = 0; i < k * k; i++)
                jac[i] = i % (k + 1) == 0 ? val(r, 1.0) : (u8(r) % 4 ? 0.0 : val(r, 0.1));
            jp = jac;
        }
        if (verbose)
            fprintf(stderr, "nnode=%d explicit_nodes=%d guess=%d jacobian=%d\n", nnode, use_nodes,
                    gp != NULL, jp != NULL);
        st = tr_solve(m, d, gp, jp);
        if (verbose)
            fprintf(stderr,
                    "tr_solve: status %d (%s) nit %d nfev %d njev %d cont %d residual %g: %s\n", st,
                    tr_strerror(st), d->nit, d->nfev, d->njev, d->cont_steps, d->residual_norm,
                    d->message);
    }
    check_msg(d->message, TR_MSGLEN, "tr_solve");
    if (!known_status(st) || st == TR_CONTINUE) FAIL("C1 tr_solve returned %d", st);
    if (o.max_nfev >= 1 && d->nfev > o.max_nfev + m->n_unknowns + TR_FUZZ_NFEV_SLACK)
        FAIL("C5 nfev %d > max_nfev %d + n_unknowns %d + %d", d->nfev, o.max_nfev, m->n_unknowns,
             TR_FUZZ_NFEV_SLACK);
    if (st >= 0) {
        const int nn = d->nnode;
        if (!(d->residual_norm <= o.tol))
            FAIL("C4 status %d with residual %g > tol %g", st, d->residual_norm, o.tol);
        if (!finite_all(d->s, nn) || !finite_all(d->pos, 3 * nn) || !finite_all(d->rot, 9 * nn) ||
            !finite_all(d->force, 3 * nn) || !finite_all(d->moment, 3 * nn) ||
            !finite_all(d->tension, nt) || !finite_all(d->slack, nt) ||
            !finite_all(d->displacement, nt))
            FAIL("C4 status %d with non-finite output", st);
        for (i = 0; i < nt; i++)
            if (d->tension[i] < 0.0 || d->slack[i] < 0.0)
                FAIL("C4 tendon %d: tension %g, slack %g", i, d->tension[i], d->slack[i]);
        /* with a fixed step count the user chose the truncation error (one RK4
         * step over the rod is legal and inaccurate); R is held to SO(3) only
         * where the core chooses the steps (automatic or adaptive) */
        /* (and the automatic step count aims at tol: with a loose tol, say
         * 1e14, a rough R is what the user asked for) */
        for (j = 0; j < nn && (o.steps == 0 || o.integrator == TR_ADAPTIVE) && o.tol <= 1e-8; j++) {
            const double *R = d->rot + 9 * j;
            for (int a = 0; a < 3; a++)
                for (int b = 0; b < 3; b++) {
                    const double dot = R[a] * R[b] + R[3 + a] * R[3 + b] + R[6 + a] * R[6 + b];
                    /* 1e-6: the fixed-step integrators keep R orthonormal to their
                     * truncation error, far below this for any accepted solve */
                    if (fabs(dot - (a == b)) > 1e-6)
                        FAIL("C4 rotation at node %d not orthonormal (%g)", j, dot - (a == b));
                }
        }
        if (u8(r) % 2) {
            const double sp = u8(r) % 2 ? rod[0] : (nl ? loads[0] : val(r, 0.1));
            const int cs = tr_compliance(m, d, sp, C);
            if (!known_status(cs)) FAIL("C1 tr_compliance returned %d", cs);
            if (cs >= 0 && !finite_all(C, 36))
                FAIL("C6 compliance status %d with non-finite entries", cs);
        }
    }
    tr_data_free(d);
    tr_model_free(m);
}

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    gsl_set_error_handler_off(); /* as the Python module does at load */
    verbose = getenv("TR_FUZZ_VERBOSE") != NULL;
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    reader r = {data, size};
    if (size == 0) return 0;
    if (u8(&r) % 8 == 0)
        fuzz_closed(&r);
    else
        fuzz_solve(&r);
    return 0;
}
