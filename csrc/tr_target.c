/*
 * tr_target.c -- an inverse-actuation target solved by the shooting system itself:
 * the residual of a tip target takes the place of the length constraint of a
 * displacement-controlled tendon, whose displacement then follows from the solution
 * (its tension or slack stays an unknown).  As many tendons as target components
 * make the system square again; its Newton iteration finds the controls and the
 * equilibrium together.
 */
#include <math.h>
#include <string.h>

#include "tendonrod.h"
#include "tr_internal.h"
#include "tru_math.h"

/* A unit basis (columns b1, b2, stored b1 (3) then b2 (3)) of the plane normal to the
 * unit vector t. */
static void normal_basis(const double t[3], double *B)
{
    double e[3] = {0.0, 0.0, 0.0}, n;
    int i, k = 0;
    for (i = 1; i < 3; i++)
        if (fabs(t[i]) < fabs(t[k])) k = i;
    e[k] = 1.0;
    tru_cross3(B, t, e);
    n = tru_norm3(B);
    for (i = 0; i < 3; i++) B[i] /= n;
    tru_cross3(B + 3, t, B);
}

int tr_model_set_target(tr_model *m, int kind, const double *values, const int *tendons, int n,
                        char *msg, size_t msglen)
{
    const int need = kind == TR_TARGET_ANGLE ? 1 : kind == TR_TARGET_DIRECTION ? 2 : 3;
    double t[3];
    int i, j;
    if (kind == TR_TARGET_NONE) {
        for (i = 0; i < m->nt; i++) m->tendon[i].target_row = -1;
        m->target_kind = TR_TARGET_NONE;
        return TR_OK;
    }
    if (kind != TR_TARGET_ANGLE && kind != TR_TARGET_DIRECTION && kind != TR_TARGET_POSITION) {
        tr_msgf(msg, msglen, "target: unknown kind %d", kind);
        return TR_EINVAL;
    }
    if ((kind == TR_TARGET_ANGLE) != (m->planar != 0)) {
        tr_msgf(msg, msglen,
                "target: a tip angle is for the planar formulation, a direction "
                "or a position for the spatial one");
        return TR_EINVAL;
    }
    if (n != need) {
        tr_msgf(msg, msglen, "target: %d tendons for %d target components", n, need);
        return TR_EINVAL;
    }
    for (j = 0; j < n; j++) {
        const int i0 = tendons[j];
        if (i0 < 0 || i0 >= m->nt || m->tendon[i0].control != TR_DISPLACEMENT) {
            tr_msgf(msg, msglen, "target: tendon %d is not a displacement-controlled tendon", i0);
            return TR_EINVAL;
        }
        for (i = 0; i < j; i++)
            if (tendons[i] == i0) {
                tr_msgf(msg, msglen, "target: tendon %d given twice", i0);
                return TR_EINVAL;
            }
    }
    for (j = 0; j < (kind == TR_TARGET_ANGLE ? 1 : 3); j++)
        if (!isfinite(values[j])) {
            tr_msgf(msg, msglen, "target: value %d is not finite", j);
            return TR_EINVAL;
        }
    memset(m->target, 0, sizeof m->target);
    if (kind == TR_TARGET_DIRECTION) {
        const double nt = tru_norm3(values);
        if (!(nt > 0.0)) {
            tr_msgf(msg, msglen, "target: the direction is zero");
            return TR_EINVAL;
        }
        for (i = 0; i < 3; i++) t[i] = values[i] / nt;
        memcpy(m->target, t, sizeof t);
        normal_basis(t, m->target + 3);
    } else {
        memcpy(m->target, values, (size_t)(kind == TR_TARGET_ANGLE ? 1 : 3) * sizeof(double));
    }
    for (i = 0; i < m->nt; i++) m->tendon[i].target_row = -1;
    for (j = 0; j < n; j++) m->tendon[tendons[j]].target_row = j;
    m->target_kind = kind;
    return TR_OK;
}

int tr_data_set_target(const tr_model *m, tr_data *d, int kind, const double *values,
                       const int *tendons, int n, char *msg, size_t msglen)
{
    tr_model *v = tr_inputs_view(m, d, msg, msglen);
    return v ? tr_model_set_target(v, kind, values, tendons, n, msg, msglen) : TR_EINVAL;
}

double tr_target_residual(const tr_model *m, const double *y, int row)
{
    if (m->target_kind == TR_TARGET_ANGLE) return y[TR_YP_TH] - m->target[0];
    if (m->target_kind == TR_TARGET_POSITION) return (y[TR_Y_P + row] - m->target[row]) / m->L;
    {
        /* the tip tangent t (third column of R) in log coordinates on the unit sphere
         * about the target: the great-circle angle toward t, atan2(|B^T t|, t_target . t),
         * along B^T t / |B^T t| (zero only at the target) */
        const double *R = y + TR_Y_R, *B = m->target + 3;
        const double tt[3] = {R[2], R[5], R[8]};
        const double b1 = tru_dot3(B, tt), b2 = tru_dot3(B + 3, tt);
        const double c = tru_dot3(m->target, tt), s = sqrt(b1 * b1 + b2 * b2);
        const double f = s > 0.0 ? atan2(s, c) / s : 1.0;
        return f * (row == 0 ? b1 : b2);
    }
}

double tr_target_displacement(const tr_model *m_, const tr_data *d, int i, double len)
{
    const tr_model *m = TR_IN(m_, d);
    const tr_tendon *t = &m->tendon[i];
    /* the length constraint solved for q: s_i + q + beta - (1 + tau/EA) rest = 0, with the
     * path-length excess len = s_i - sref and rest = sref + rest_dev */
    return t->rest_dev + (isfinite(t->EA) ? d->tau[i] / t->EA : 0.0) * t->rest - d->beta[i] - len;
}
