/* A cold solve may return its last Newton Jacobian (finite differences, then Broyden
 * updates) as the Jacobian at the solution, and estimate the condition with it, when it
 * was differenced close to the solution (solve_condition, TR_J_MOVE, TR_COND_TRUST).
 * Checked against a fresh finite-difference Jacobian at the solution: a Kirchhoff rod
 * under a small end moment and a larger one, with a transverse tip force (the cold guess
 * is close for the first, far for the second).  Prints "ok" and exits 0 when every returned Jacobian agrees with the fresh one to
 * 1e-3 (Frobenius, relative) and its condition to a factor 2. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <gsl/gsl_errno.h>
#include "tendonrod.h"
#include "tr_internal.h" /* reads the workspace's fields */
#include "tr_data.h"

static int one(double M, double F)
{
    const double L = 0.2, EI = 0.0112;
    const double rod[6] = {L, EI, EI / 1.3, 1e9, 1e9, 1};
    const double loads[7] = {L, F, 0, 0, 0, M, 0};
    const double dist[3] = {0, 0, 0};
    double J[64], num = 0.0, den = 0.0, c0, c1;
    char msg[512];
    tr_options o = tr_default_options();
    tr_model *m = NULL;
    tr_data *d;
    int st, i, nfev, k;
    if (tr_model_alloc(&m, rod, NULL, 0, loads, 1, dist, &o, msg, sizeof msg) != TR_OK) {
        fprintf(stderr, "model: %s\n", msg);
        return 1;
    }
    d = tr_data_alloc(m, &o, 11, NULL, msg, sizeof msg);
    if (!d) return 1;
    st = tr_solve(m, d, NULL, NULL);
    if (st != TR_OK) {
        fprintf(stderr, "solve (M %g, F %g): %s\n", M, F, d->message);
        return 1;
    }
    k = d->k;
    memcpy(J, d->J, (size_t)k * k * sizeof(double));
    c0 = d->jacobian_cond;
    nfev = d->nfev;
    /* the reference: a fresh Jacobian at the converged unknowns */
    if (tr_fd_jacobian(m, d) != TR_OK) return 1;
    c1 = tr_jacobian_cond(d);
    for (i = 0; i < k * k; i++) {
        num += (J[i] - d->J[i]) * (J[i] - d->J[i]);
        den += d->J[i] * d->J[i];
    }
    /* the fresh Jacobian of the old rule is bitwise the one at the solution; a reused one
     * differs by the Broyden updates and the move (<= TR_J_MOVE): measured 2.3e-4 at most
     * on bench/solve.py's scenes, 1e-3 leaves room; the condition within 0.67x..1.95x over
     * the stress suite (bench/results/error_estimate.md) */
    if (!(sqrt(num / den) <= 1e-3) || !(c0 <= 2.0 * c1 && c1 <= 2.0 * c0)) {
        fprintf(stderr, "M %g F %g: |dJ|/|J| %.3g, cond %.6g against fresh %.6g (nfev %d)\n", M, F,
                sqrt(num / den), c0, c1, nfev);
        return 1;
    }
    tr_data_free(d);
    tr_model_free(m);
    return 0;
}

int main(void)
{
    gsl_set_error_handler_off();
    if (one(1e-5, 0.0) || one(1e-5, 1e-4) || one(0.05, 0.1) || one(0.02, -0.3)) return 1;
    puts("ok");
    return 0;
}
