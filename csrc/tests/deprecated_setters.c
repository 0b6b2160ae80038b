/* The deprecated setters of a compiled model (tr_model_set_values, _pretension, _target)
 * against what replaced them, through the public header only.  Each check solves the
 * same scene three ways and requires bitwise the same outputs (status, evaluations, tip
 * state, tensions, slacks, displacements):
 *   A: the model compiled with the new values;
 *   B: a model compiled with other values, then given the new ones by the deprecated
 *      setter before any workspace exists (the setter sets the defaults a workspace
 *      copies);
 *   C: the model compiled with the other values, its workspace given the new ones by
 *      tr_data_set_* (the model untouched).
 * Checks: actuation values and a tip load (a displacement- and a tension-controlled
 * tendon, spatial), pretensions (two opposing displacement-controlled tendons, planar),
 * a tip-angle target (planar).  Then a setter's refusal: a negative tension is refused by
 * both with TR_EINVAL and a message, the model and the workspace left as they were.
 * Prints "ok" and exits 0, or what differed and exits 1.
 * Build from the repository root:
 *   cc -std=c99 -O2 -Icsrc csrc/tests/deprecated_setters.c csrc/tr_*.c \
 *      $(pkg-config --cflags --libs gsl) -lm -o /tmp/deprecated_setters */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <gsl/gsl_errno.h>

#include "tendonrod.h"

enum { NT = 2, NOUT = 3 + 18 + 3 * NT };

static const double PI = 3.14159265358979323846;

typedef struct {
    double rod[TR_ROD_NCOL];
    double tendon[NT * TR_TD_NCOL];
    double load[TR_LD_NCOL];
    int planar; /* tendons in the x-z plane and an x load */
} scene;

/* A Cosserat rod (L = 0.2 m, steel, d = 0.8 mm) with two tendons at 10 mm and a tip load. */
static void base_scene(scene *sc, int planar, int control1)
{
    const double L = 0.2, EI = 207e9 * PI * pow(0.8e-3, 4) / 64;
    int i;
    memset(sc, 0, sizeof *sc);
    sc->rod[TR_ROD_L] = L, sc->rod[TR_ROD_EI] = EI, sc->rod[TR_ROD_GJ] = EI / 1.3;
    sc->rod[TR_ROD_EA] = 207e9 * PI * 0.16e-6, sc->rod[TR_ROD_GA] = sc->rod[TR_ROD_EA] / 2.6;
    sc->rod[TR_ROD_KIRCHHOFF] = 0;
    for (i = 0; i < NT; i++) {
        double *t = sc->tendon + TR_TD_NCOL * i;
        t[TR_TD_OFFSET] = 0.01, t[TR_TD_ANGLE] = planar ? PI * i : PI / 2 * i;
        t[TR_TD_EA] = 2e3, t[TR_TD_END] = L;
        t[TR_TD_CONTROL] = i == 1 ? control1 : TR_DISPLACEMENT;
    }
    sc->load[TR_LD_S] = L;
    sc->planar = planar;
}

static tr_model *compile(const scene *sc, const tr_options *o)
{
    const double dist[3] = {0, 0, 0};
    char msg[TR_MSGLEN];
    tr_model *m = NULL;
    if (tr_model_alloc(&m, sc->rod, sc->tendon, NT, sc->load, 1, dist, o, msg, sizeof msg) !=
        TR_OK) {
        printf("compile failed: %s\n", msg);
        return NULL;
    }
    return m;
}

/* status, nfev, nit, the tip state, tensions, slacks and displacements. */
static void outputs(const tr_data *d, double *out)
{
    tr_result r;
    tr_outputs o;
    int i;
    tr_data_result(d, &r);
    tr_data_outputs(d, &o);
    out[0] = r.status, out[1] = r.nfev, out[2] = r.nit;
    for (i = 0; i < 18; i++) out[3 + i] = o.tip[i];
    for (i = 0; i < NT; i++) {
        out[21 + i] = o.tension[i];
        out[21 + NT + i] = o.slack[i];
        out[21 + 2 * NT + i] = o.displacement[i];
    }
}

static int solve_into(const tr_model *m, tr_data *d, double *out)
{
    tr_solve(m, d, NULL, NULL);
    outputs(d, out);
    return (int)out[0];
}

static int same(const char *what, const double *a, const double *b)
{
    int i;
    for (i = 0; i < NOUT; i++)
        if (memcmp(a + i, b + i, sizeof(double)) != 0 && !(isnan(a[i]) && isnan(b[i]))) {
            printf("%s: output %d differs: %.17g vs %.17g\n", what, i, a[i], b[i]);
            return 0;
        }
    return 1;
}

/* The three ways for one change (kind 0: values and load, 1: pretension, 2: target). */
static int check(const char *name, int kind, int planar, int control1)
{
    const tr_options o = tr_default_options();
    scene old, new_;
    double value[NT], load[6], pre[NT], target = 0.6, outA[NOUT], outB[NOUT], outC[NOUT];
    const int tendons[1] = {0};
    char msg[TR_MSGLEN];
    tr_model *mA, *mB, *mC;
    tr_data *dA, *dB, *dC;
    int i, ok = 1, st;
    base_scene(&old, planar, control1);
    old.tendon[TR_TD_VALUE] = 2e-3;
    old.tendon[TR_TD_NCOL + TR_TD_VALUE] = control1 == TR_TENSION ? 1.0 : -1e-3;
    old.load[TR_LD_F] = 0.05;
    new_ = old;
    if (kind == 0) {
        new_.tendon[TR_TD_VALUE] = 3.5e-3;
        new_.tendon[TR_TD_NCOL + TR_TD_VALUE] = control1 == TR_TENSION ? 2.5 : -2e-3;
        new_.load[TR_LD_F] = -0.08, new_.load[TR_LD_F + 1] = planar ? 0.0 : 0.03;
    } else if (kind == 1) {
        new_.tendon[TR_TD_PRETENSION] = 3.0;
        new_.tendon[TR_TD_NCOL + TR_TD_PRETENSION] = 3.0;
    }
    for (i = 0; i < NT; i++) {
        value[i] = new_.tendon[TR_TD_NCOL * i + TR_TD_VALUE];
        pre[i] = new_.tendon[TR_TD_NCOL * i + TR_TD_PRETENSION];
    }
    for (i = 0; i < 6; i++) load[i] = new_.load[TR_LD_F + i];
    mA = compile(&new_, &o), mB = compile(&old, &o), mC = compile(&old, &o);
    if (!mA || !mB || !mC) return 0;
    if (kind == 0)
        st = tr_model_set_values(mB, value, load, NULL, msg, sizeof msg);
    else if (kind == 1)
        st = tr_model_set_pretension(mB, pre, msg, sizeof msg);
    else
        st = tr_model_set_target(mB, TR_TARGET_ANGLE, &target, tendons, 1, msg, sizeof msg);
    if (kind == 2 && st == TR_OK)
        st = tr_model_set_target(mA, TR_TARGET_ANGLE, &target, tendons, 1, msg, sizeof msg);
    if (st != TR_OK) {
        printf("%s: the deprecated setter refused: %s\n", name, msg);
        return 0;
    }
    dA = tr_data_alloc(mA, &o, 11, NULL, msg, sizeof msg);
    dB = tr_data_alloc(mB, &o, 11, NULL, msg, sizeof msg);
    dC = tr_data_alloc(mC, &o, 11, NULL, msg, sizeof msg);
    if (!dA || !dB || !dC) {
        printf("%s: workspace: %s\n", name, msg);
        return 0;
    }
    if (kind == 0)
        st = tr_data_set_values(mC, dC, value, load, NULL, msg, sizeof msg);
    else if (kind == 1)
        st = tr_data_set_pretension(mC, dC, pre, msg, sizeof msg);
    else
        st = tr_data_set_target(mC, dC, TR_TARGET_ANGLE, &target, tendons, 1, msg, sizeof msg);
    if (st != TR_OK) {
        printf("%s: tr_data_set_* refused: %s\n", name, msg);
        ok = 0;
    }
    if (ok && !TR_SUCCEEDED(solve_into(mA, dA, outA))) {
        tr_result r;
        tr_data_result(dA, &r);
        printf("%s: the reference solve failed: %s\n", name, r.message);
        ok = 0;
    }
    if (ok) {
        solve_into(mB, dB, outB);
        solve_into(mC, dC, outC);
        ok = same(name, outA, outB) && same(name, outA, outC);
    }
    tr_data_free(dA), tr_data_free(dB), tr_data_free(dC);
    tr_model_free(mA), tr_model_free(mB), tr_model_free(mC);
    return ok;
}

/* A refused value leaves the model's defaults and the workspace's values as they were:
 * the solves after the refusal are bitwise those before it. */
static int check_refusal(void)
{
    const tr_options o = tr_default_options();
    scene sc;
    double before[NOUT], after[NOUT], value[NT] = {2e-3, -1.0};
    char msg[TR_MSGLEN] = "";
    tr_model *m;
    tr_data *d;
    int ok = 1;
    base_scene(&sc, 0, TR_TENSION);
    sc.tendon[TR_TD_VALUE] = 2e-3, sc.tendon[TR_TD_NCOL + TR_TD_VALUE] = 1.0;
    if (!(m = compile(&sc, &o)) || !(d = tr_data_alloc(m, &o, 11, NULL, msg, sizeof msg))) return 0;
    solve_into(m, d, before);
    if (tr_model_set_values(m, value, NULL, NULL, msg, sizeof msg) != TR_EINVAL || !msg[0]) {
        printf("refusal: tr_model_set_values took a negative tension\n");
        ok = 0;
    }
    msg[0] = '\0';
    if (tr_data_set_values(m, d, value, NULL, NULL, msg, sizeof msg) != TR_EINVAL || !msg[0]) {
        printf("refusal: tr_data_set_values took a negative tension\n");
        ok = 0;
    }
    tr_forget(d);
    solve_into(m, d, after);
    ok = ok && same("refusal: the workspace", before, after);
    tr_data_free(d);
    /* and a fresh workspace of the model: its defaults unchanged */
    if (ok && (d = tr_data_alloc(m, &o, 11, NULL, msg, sizeof msg))) {
        solve_into(m, d, after);
        ok = same("refusal: the model's defaults", before, after);
        tr_data_free(d);
    }
    tr_model_free(m);
    return ok;
}

int main(void)
{
    int ok = 1;
    gsl_set_error_handler_off();
    ok &= check("values and load (spatial, a tension-controlled tendon)", 0, 0, TR_TENSION);
    ok &= check("values and load (spatial)", 0, 0, TR_DISPLACEMENT);
    ok &= check("pretension (opposing tendons, planar)", 1, 1, TR_DISPLACEMENT);
    ok &= check("tip-angle target (planar)", 2, 1, TR_DISPLACEMENT);
    ok &= check_refusal();
    printf("%s\n", ok ? "ok" : "FAILED");
    return ok ? 0 : 1;
}
