/*
 * solve_scene.c -- the C API of libtendonrod in one scene.
 *
 * A Kirchhoff rod (the README's spring-steel wire, L = 0.2 m) with one parallel tendon
 * at offset r = 8 mm pulled with a tension tau: the tendon's pull is a pure moment
 * tau r at every section, so the rod bends into a circular arc of curvature
 * kappa = tau r / EI, and the tip sits at ((1 - cos kappa L) / kappa, 0,
 * sin(kappa L) / kappa).  The solve is checked against that arc (a closed form the
 * solver does not use), then the same robot is actuated by the displacement the solve
 * reported, and a tip load is added.  Exit status 0 when both solves succeed and the
 * first tip is within 1e-9 L of the arc.
 *
 *   cc solve_scene.c $(pkg-config --cflags --libs tendonrod) -lm
 */
#include <math.h>
#include <stdio.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_math.h> /* M_PI */
#include <tendonrod.h>

int main(void)
{
    const double L = 0.2, d = 0.8e-3, E = 207e9, G = 79.6e9; /* m, m, Pa, Pa */
    const double I = M_PI * pow(d, 4) / 64, A = M_PI * d * d / 4;
    const double EI = E * I, r = 0.008, tau = 1.0; /* N m^2, m, N */
    /* rod: [L, EI, GJ, EA, GA, kirchhoff] */
    const double rod[TR_ROD_NCOL] = {L, EI, G * 2 * I, E * A, G * A, 1};
    /* one tendon: [offset, angle, slope, EA, end, control, value, pretension] */
    double tendon[TR_TD_NCOL] = {r, 0.0, 0.0, INFINITY, L, TR_TENSION, tau, 0.0};
    const double no_dist[3] = {0, 0, 0};
    const double kappa = tau * r / EI;
    const double arc_x = (1 - cos(kappa * L)) / kappa, arc_z = sin(kappa * L) / kappa;
    char msg[TR_MSGLEN];
    tr_options o = tr_default_options();
    tr_model *m = NULL;
    tr_data *dat;
    tr_result res;  /* what a solve did (counts, message) */
    tr_outputs out; /* its state: tip, tensions, displacements, nodes */
    double err, q;
    int st;

    gsl_set_error_handler_off(); /* the core reports GSL failures as status codes */

    /* 1. tension control: the closed-form arc */
    if (tr_model_alloc(&m, rod, tendon, 1, NULL, 0, no_dist, &o, msg, sizeof msg) != TR_OK) {
        fprintf(stderr, "model: %s\n", msg);
        return 1;
    }
    dat = tr_data_alloc(m, &o, TR_DEFAULT_NODES, NULL, msg, sizeof msg);
    if (!dat) {
        fprintf(stderr, "workspace: %s\n", msg);
        return 1;
    }
    st = tr_solve(m, dat, NULL, NULL);
    tr_data_result(dat, &res);
    tr_data_outputs(dat, &out);
    printf("tension %.3g N: %s (%d iterations): %s\n", tau, tr_strerror(st), res.nit, res.message);
    if (!TR_SUCCEEDED(st)) return 1;
    err = hypot(out.tip[0] - arc_x, out.tip[2] - arc_z);
    printf("  tip (%.9f, %.9f, %.9f) m, arc (%.9f, 0, %.9f) m, |difference| %.2e m\n", out.tip[0],
           out.tip[1], out.tip[2], arc_x, arc_z, err);
    q = out.displacement[0];
    printf("  tendon displacement %.6f m (arc: r kappa L = %.6f m)\n", q, r * kappa * L);
    tr_data_free(dat);
    tr_model_free(m);
    /* 1e-9 L: the solver's default tol is 1e-10 on the scaled residual, and the step
     * verification keeps the truncation error below it; 1e-9 L leaves a factor 10 */
    if (!(err <= 1e-9 * L)) return 1;

    /* 2. the same robot, its tendon locked at that displacement, 0.1 N down at the tip */
    tendon[TR_TD_CONTROL] = TR_DISPLACEMENT;
    tendon[TR_TD_VALUE] = q;
    const double load[TR_LD_NCOL] = {L, 0, 0, -0.1, 0, 0, 0};
    if (tr_model_alloc(&m, rod, tendon, 1, load, 1, no_dist, &o, msg, sizeof msg) != TR_OK) {
        fprintf(stderr, "model: %s\n", msg);
        return 1;
    }
    dat = tr_data_alloc(m, &o, TR_DEFAULT_NODES, NULL, msg, sizeof msg);
    if (!dat) {
        fprintf(stderr, "workspace: %s\n", msg);
        return 1;
    }
    st = tr_solve(m, dat, NULL, NULL);
    tr_data_outputs(dat, &out);
    printf("locked at q = %.6f m, 0.1 N down: %s; tip (%.6f, %.6f, %.6f) m, tension %.4f N\n", q,
           tr_strerror(st), out.tip[0], out.tip[1], out.tip[2], out.tension[0]);
    tr_data_free(dat);
    tr_model_free(m);
    return TR_SUCCEEDED(st) ? 0 : 1;
}
