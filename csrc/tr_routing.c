/*
 * tr_routing.c -- general tendon paths: helices and piecewise polynomials (cubic splines
 * of sampled or given paths, straight pieces between disks) in the body frame.
 *
 * A path's rows are read and checked here; every knot of a piecewise path is a
 * breakpoint, so each integration segment lies in one piece, found once per segment
 * (m->seg_piece) and evaluated in the right-hand side by tr_route_eval (tr_internal.h).
 * Linear tendons keep their closed form in tr_rod.c.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tendonrod.h"
#include "tr_internal.h"

int tr_read_routes(tr_model *m, const double *routes, int nroute, char *msg, size_t msglen)
{
    int j, c;
    m->nroute = nroute;
    m->n_routed = 0;
    for (j = 0; j < nroute; j++) {
        const double *row = routes + TR_RT_NCOL * j;
        int i, kind;
        tr_tendon *t;
        for (c = 0; c < TR_RT_NCOL; c++)
            if (!isfinite(row[c])) {
                tr_msgf(msg, msglen, "routes[%d][%d] = %g must be finite", j, c, row[c]);
                return TR_EINVAL;
            }
        if (!(row[TR_RT_TENDON] >= 0.0 && row[TR_RT_TENDON] < m->nt) ||
            row[TR_RT_TENDON] != floor(row[TR_RT_TENDON])) {
            tr_msgf(msg, msglen, "routes[%d] tendon = %g must be a tendon index in [0, %d)", j,
                    row[TR_RT_TENDON], m->nt);
            return TR_EINVAL;
        }
        if (row[TR_RT_KIND] != TR_ROUTE_HELIX && row[TR_RT_KIND] != TR_ROUTE_PIECE) {
            tr_msgf(msg, msglen, "routes[%d] kind = %g must be %d (helix) or %d (piece)", j,
                    row[TR_RT_KIND], TR_ROUTE_HELIX, TR_ROUTE_PIECE);
            return TR_EINVAL;
        }
        i = (int)row[TR_RT_TENDON];
        kind = (int)row[TR_RT_KIND];
        t = &m->tendon[i];
        if (t->route == TR_ROUTE_LINEAR) {
            /* the first row of this tendon starts at the base */
            if (fabs(row[TR_RT_S0]) > TR_KNOT_TOL * m->L) {
                tr_msgf(msg, msglen, "routes[%d]: tendon %d's path must start at s = 0, not %g m",
                        j, i, row[TR_RT_S0]);
                return TR_EINVAL;
            }
            t->route = kind;
            m->n_routed++;
        } else if (kind == TR_ROUTE_HELIX || t->route == TR_ROUTE_HELIX) {
            tr_msgf(msg, msglen, "routes[%d]: tendon %d has a helix and other rows", j, i);
            return TR_EINVAL;
        } else {
            const double *prev = routes + TR_RT_NCOL * (j - 1);
            if (j == 0 || prev[TR_RT_TENDON] != row[TR_RT_TENDON] ||
                fabs(prev[TR_RT_S1] - row[TR_RT_S0]) > TR_KNOT_TOL * m->L) {
                tr_msgf(msg, msglen,
                        "routes[%d]: tendon %d's pieces must follow each other in order "
                        "(s0 = %g m, the previous piece ends elsewhere)",
                        j, i, row[TR_RT_S0]);
                return TR_EINVAL;
            }
        }
        if (!(row[TR_RT_S1] > row[TR_RT_S0]) || row[TR_RT_S1] > t->t * (1.0 + TR_KNOT_TOL)) {
            tr_msgf(msg, msglen,
                    "routes[%d] [s0, s1] = [%g, %g] m must be increasing within "
                    "[0, end = %g]",
                    j, row[TR_RT_S0], row[TR_RT_S1], t->t);
            return TR_EINVAL;
        }
        if (kind == TR_ROUTE_HELIX) {
            if (fabs(row[TR_RT_P]) * m->L > TR_ROD_MAX) {
                tr_msgf(msg, msglen, "routes[%d] twist = %g rad/m is out of range", j,
                        row[TR_RT_P]);
                return TR_EINVAL;
            }
            t->twist = row[TR_RT_P];
        }
        memcpy(m->route + TR_RT_NCOL * j, row, TR_RT_NCOL * sizeof(double));
    }
    /* every routed tendon's path reaches its anchor */
    for (j = 0; j < nroute; j++) {
        const double *row = m->route + TR_RT_NCOL * j;
        const int last = j == nroute - 1 || row[TR_RT_NCOL + TR_RT_TENDON] != row[TR_RT_TENDON];
        const tr_tendon *t = &m->tendon[(int)row[TR_RT_TENDON]];
        if (last && fabs(row[TR_RT_S1] - t->t) > TR_KNOT_TOL * m->L) {
            tr_msgf(msg, msglen,
                    "routes[%d]: tendon %d's path ends at %g m, not at its anchor %g m", j,
                    (int)row[TR_RT_TENDON], row[TR_RT_S1], t->t);
            return TR_EINVAL;
        }
    }
    return TR_OK;
}

int tr_route_pieces(tr_model *m)
{
    int k, j;
    if (m->n_routed == 0) return TR_OK;
    m->seg_piece = (int *)malloc((size_t)m->nseg * m->nt * sizeof(int));
    if (!m->seg_piece) return TR_ENOMEM;
    for (k = 0; k < m->nseg * m->nt; k++) m->seg_piece[k] = -1;
    for (k = 0; k < m->nseg; k++) {
        const double mid = 0.5 * (m->bp[k] + m->bp[k + 1]);
        for (j = 0; j < m->nroute; j++) {
            const double *row = m->route + TR_RT_NCOL * j;
            const int i = (int)row[TR_RT_TENDON];
            if (m->tendon[i].end_bp > k && row[TR_RT_S0] <= mid &&
                (row[TR_RT_S1] >= mid || m->seg_piece[k * m->nt + i] < 0))
                m->seg_piece[k * m->nt + i] = j;
        }
    }
    return TR_OK;
}

void tr_tendon_offset(const tr_model *m, int i, int seg, double s, double r[3], double rp[3])
{
    const tr_tendon *t = &m->tendon[i];
    if (t->route == TR_ROUTE_LINEAR) {
        const double rho = t->a * s + t->b;
        r[0] = rho * t->cphi;
        r[1] = rho * t->sphi;
        rp[0] = t->a * t->cphi;
        rp[1] = t->a * t->sphi;
    } else {
        double rpp[2];
        tr_route_eval(m, t, i, seg, s, r, rp, rpp);
    }
    r[2] = rp[2] = 0.0;
}
