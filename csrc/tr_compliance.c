/*
 * tr_compliance.c -- the compliance of a solved scene by the implicit function
 * theorem on the shooting map: with the residual F(x, p) = 0 at the solution and
 * the pose Y(x) at the probe, dY/dp = -Y_x J^-1 F_p (central differences, spatial
 * formulation), prescribed displacements and tensions held fixed.
 */
#include <math.h>
#include <string.h>

#include "tendonrod.h"
#include "tr_internal.h"

int tr_compliance(const tr_model *m, tr_data *d, double s_probe, double C[36])
{
    const int k = d->k;
    const double hx = TR_CD_H;
    int pb = -1, b, i, j, q, status;
    double R0[9];
    for (b = 1; b <= m->nseg; b++)
        if (fabs(m->bp[b] - s_probe) <= 1e-12 * m->L) pb = b;
    if (pb < 0) {
        tr_set_message(d,
                       "compliance: s = %g m is not a breakpoint of the model (add a zero "
                       "point load there)",
                       s_probe);
        return TR_EINVAL;
    }
    if (m->planar) {
        tr_set_message(d, "compliance needs the spatial formulation (force_spatial)");
        return TR_EINVAL;
    }
    d->probe_bp = pb;
    memset(d->probe, 0, sizeof d->probe);
    d->lam_act = d->lam_load = 1.0;
    tr_poll_start(d); /* a budget of its own; the caller's interrupt still applies */
    status = tr_residual(m, d, d->x, d->f);
    if (status != TR_OK) goto done;
    memcpy(R0, d->probe_state + 3, sizeof R0);
    /* d(residual)/dx and d(pose at probe)/dx, central differences */
    for (j = 0; j < k; j++) {
        double Yp[12];
        memcpy(d->xt, d->x, (size_t)k * sizeof(double));
        d->xt[j] = d->x[j] + hx;
        status = tr_residual(m, d, d->xt, d->ft);
        if (status != TR_OK) goto done;
        memcpy(Yp, d->probe_state, sizeof Yp);
        for (i = 0; i < k; i++) d->work[i] = d->ft[i];
        d->xt[j] = d->x[j] - hx;
        status = tr_residual(m, d, d->xt, d->ft);
        if (status != TR_OK) goto done;
        for (i = 0; i < k; i++) d->J[i * k + j] = (d->work[i] - d->ft[i]) / (2.0 * hx);
        {
            double dR[9], W[9];
            for (i = 0; i < 3; i++) d->Yx[i * k + j] = (Yp[i] - d->probe_state[i]) / (2.0 * hx);
            for (i = 0; i < 9; i++) dR[i] = (Yp[3 + i] - d->probe_state[3 + i]) / (2.0 * hx);
            /* W = dR R0^T (skew): dtheta = vee(W) */
            for (i = 0; i < 3; i++)
                for (q = 0; q < 3; q++)
                    W[3 * i + q] = dR[3 * i] * R0[3 * q] + dR[3 * i + 1] * R0[3 * q + 1] +
                                   dR[3 * i + 2] * R0[3 * q + 2];
            d->Yx[3 * k + j] = 0.5 * (W[7] - W[5]);
            d->Yx[4 * k + j] = 0.5 * (W[2] - W[6]);
            d->Yx[5 * k + j] = 0.5 * (W[3] - W[1]);
        }
    }
    d->njev++;
    /* d(residual)/d(probe load) */
    for (q = 0; q < 6; q++) {
        const double hp = hx * (q < 3 ? m->F_s : m->M_s);
        memset(d->probe, 0, sizeof d->probe);
        d->probe[q] = hp;
        status = tr_residual(m, d, d->x, d->ft);
        if (status != TR_OK) goto done;
        for (i = 0; i < k; i++) d->work[i] = d->ft[i];
        d->probe[q] = -hp;
        status = tr_residual(m, d, d->x, d->ft);
        if (status != TR_OK) goto done;
        for (i = 0; i < k; i++) d->Fp[i * 6 + q] = (d->work[i] - d->ft[i]) / (2.0 * hp);
    }
    memset(d->probe, 0, sizeof d->probe);
    if (tr_lu_factor(d) != 0) {
        tr_set_message(d, "compliance: the Jacobian at the solution is singular");
        status = TR_ESINGULAR;
        goto done;
    }
    /* du/dp = -J^-1 Fp; C = Yx du/dp */
    for (q = 0; q < 6; q++) {
        for (i = 0; i < k; i++) d->work[i] = -d->Fp[i * 6 + q];
        if (tr_lu_solve(d, d->work, d->ft) != 0) {
            status = TR_ESINGULAR;
            goto done;
        }
        for (i = 0; i < 6; i++) {
            double c = 0.0;
            for (j = 0; j < k; j++) c += d->Yx[i * k + j] * d->ft[j];
            C[6 * i + q] = c;
        }
    }
    status = TR_OK;
done:
    d->probe_bp = -1;
    memset(d->probe, 0, sizeof d->probe);
    if (status == TR_EBUDGET)
        tr_set_message(d,
                       "the work budget ran out while linearising (max_work = %.3g units; the "
                       "compliance needs 2 k + 12 evaluations, k = %d unknowns): raise "
                       "Options.max_work",
                       d->opt.max_work, k);
    else if (status == TR_ESINGULAR)
        tr_set_message(d, "compliance: the Jacobian at the solution is singular");
    else if (status != TR_OK && status != TR_EINVAL)
        tr_set_message(d, "compliance failed: %s", tr_strerror(status));
    return status;
}
