/*
 * tr_model.c -- compile a scene into the smallest problem that represents it.
 *
 * Stages: validate the rod, read and validate the tendons and the loads, place the
 * breakpoints (tendon anchors, point loads and shooting nodes inside (0, L]) with
 * the active-tendon lists per segment, choose the formulation (planar or spatial;
 * unknowns; path-length states only for displacement-controlled tendons), set the
 * scales, then the tendon-set checks of tr_tendons.c.  Also: deep copies, and the same
 * scene compiled with another number of shooting segments (the confirmation's).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tendonrod.h"
#include "tr_internal.h"

void tr_model_free(tr_model *m)
{
    if (!m) return;
    free(m->tendon);
    free(m->load);
    free(m->bp);
    free(m->bpF);
    free(m->bpM);
    free(m->seg_act_start);
    free(m->seg_act);
    free(m->bp_node);
    free(m->bp_jump);
    free(m->dload);
    free(m->seg_pdist);
    free(m->sec);
    free(m->seg_rod);
    free(m->route);
    free(m->seg_piece);
    free(m);
}

static int cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Index of the breakpoint nearest to s. */
static int find_bp(const tr_model *m, double s)
{
    int k, best = 0;
    double dmin = INFINITY;
    for (k = 0; k <= m->nseg; k++) {
        const double dd = fabs(m->bp[k] - s);
        if (dd < dmin) {
            dmin = dd;
            best = k;
        }
    }
    return best;
}

static int check_rod(const double rod[6], char *msg, size_t msglen)
{
    const char *names[6] = {"rod length L", "rod EI", "rod GJ",
                            "rod EA",       "rod GA", "rod kirchhoff"};
    int i;
    for (i = 0; i < 5; i++) {
        /* EA, GA may be inf for a Kirchhoff rod only */
        const int may_inf = (i >= TR_ROD_EA && rod[TR_ROD_KIRCHHOFF] != 0.0);
        if (!(rod[i] > 0.0) || (!may_inf && !isfinite(rod[i]))) {
            tr_msgf(msg, msglen, "%s = %g must be finite and > 0", names[i], rod[i]);
            return TR_EINVAL;
        }
    }
    for (i = 0; i < 5; i++) {
        const int axial = i >= TR_ROD_EA;
        const double lo = axial ? TR_EA_MIN : TR_ROD_MIN, hi = axial ? TR_EA_MAX : TR_ROD_MAX;
        if (isfinite(rod[i]) && (rod[i] > hi || rod[i] < lo)) {
            tr_msgf(msg, msglen,
                    "rod values out of range: L = %g m, EI = %g, GJ = %g N m^2, EA = %g, GA = %g "
                    "N (L, EI, GJ within [%g, %g]; EA, GA within [%g, %g] or inf for a "
                    "Kirchhoff rod)",
                    rod[0], rod[1], rod[2], rod[3], rod[4], TR_ROD_MIN, TR_ROD_MAX, TR_EA_MIN,
                    TR_EA_MAX);
            return TR_EINVAL;
        }
    }
    if (rod[TR_ROD_KIRCHHOFF] != 0.0 && rod[TR_ROD_KIRCHHOFF] != 1.0) {
        tr_msgf(msg, msglen, "%s = %g must be 0 or 1", names[5], rod[5]);
        return TR_EINVAL;
    }
    return TR_OK;
}

/* Read tendon i from its row; the largest offset of a displacement-controlled
 * tendon goes into *rmax. */
static int read_tendon(tr_model *m, int i, const double *row, double *rmax, char *msg,
                       size_t msglen)
{
    static const char *col[8] = {"offset", "angle",   "slope", "EA",
                                 "end",    "control", "value", "pretension"};
    tr_tendon *t = &m->tendon[i];
    int c;
    for (c = 0; c < TR_TD_NCOL; c++)
        if (isnan(row[c]) || (c != TR_TD_EA && !isfinite(row[c]))) {
            tr_msgf(msg, msglen, "tendons[%d] %s = %g must be finite", i, col[c], row[c]);
            return TR_EINVAL;
        }
    t->b = row[TR_TD_OFFSET];
    t->phi = row[TR_TD_ANGLE];
    t->a = row[TR_TD_SLOPE];
    t->EA = row[TR_TD_EA];
    t->t = row[TR_TD_END];
    t->value = row[TR_TD_VALUE];
    t->pretension = row[TR_TD_PRETENSION];
    if (!(t->EA > 0.0) || (isfinite(t->EA) && (t->EA < TR_EA_MIN || t->EA > TR_EA_MAX))) {
        tr_msgf(msg, msglen, "tendons[%d] EA = %g must lie in [%g, %g] N, or be inf (inextensible)",
                i, t->EA, TR_EA_MIN, TR_EA_MAX);
        return TR_EINVAL;
    }
    {
        /* offsets: 0, or within the range the scales EI/(r L) of the solver can carry */
        const double rb = fabs(t->b), re = fabs(t->a * row[TR_TD_END] + t->b);
        if ((rb != 0.0 && !(rb >= TR_ROD_MIN && rb <= TR_ROD_MAX)) ||
            (re != 0.0 && !(re >= TR_ROD_MIN && re <= TR_ROD_MAX)) || !(fabs(t->a) <= TR_ROD_MAX)) {
            tr_msgf(msg, msglen,
                    "tendons[%d] offset = %g m (%g m at its anchor), slope = %g: a nonzero offset "
                    "must lie in [%g, %g] m",
                    i, t->b, t->a * row[TR_TD_END] + t->b, t->a, TR_ROD_MIN, TR_ROD_MAX);
            return TR_EINVAL;
        }
    }
    if (!(t->t > 0.0) || t->t > m->L * (1.0 + TR_BP_MERGE)) {
        tr_msgf(msg, msglen, "tendons[%d] end = %g m must lie in (0, L = %g]", i, t->t, m->L);
        return TR_EINVAL;
    }
    if (t->t > m->L) t->t = m->L;
    /* compared as a double first: converting an out-of-range double to int is
     * undefined behaviour */
    if (row[TR_TD_CONTROL] != 0.0 && row[TR_TD_CONTROL] != 1.0) {
        tr_msgf(msg, msglen, "tendons[%d] control = %g must be 0 (displacement) or 1 (tension)", i,
                row[TR_TD_CONTROL]);
        return TR_EINVAL;
    }
    t->control = row[TR_TD_CONTROL] == 1.0 ? TR_TENSION : TR_DISPLACEMENT;
    if (t->control == TR_TENSION && t->value < 0.0) {
        tr_msgf(msg, msglen, "tendons[%d] tension = %g N must be >= 0 (a tendon cannot push)", i,
                t->value);
        return TR_EINVAL;
    }
    if (t->pretension < 0.0) {
        tr_msgf(msg, msglen, "tendons[%d] pretension = %g N must be >= 0", i, t->pretension);
        return TR_EINVAL;
    }
    if (t->control == TR_DISPLACEMENT) {
        const double rb = fabs(t->b), re = fabs(t->a * t->t + t->b);
        if (rb > *rmax) *rmax = rb;
        if (re > *rmax) *rmax = re;
    }
    t->cphi = cos(t->phi);
    t->sphi = sin(t->phi);
    t->wref = sqrt(1.0 + t->a * t->a);
    tr_tendon_base_frame_straight(t);
    return TR_OK;
}

static int read_loads(tr_model *m, const double *loads, char *msg, size_t msglen)
{
    int i, c;
    for (i = 0; i < m->nl; i++) {
        const double *row = loads + TR_LD_NCOL * i;
        for (c = 0; c < TR_LD_NCOL; c++)
            if (!isfinite(row[c])) {
                tr_msgf(msg, msglen, "loads[%d][%d] = %g must be finite", i, c, row[c]);
                return TR_EINVAL;
            }
        if (row[TR_LD_S] < 0.0 || row[TR_LD_S] > m->L * (1.0 + TR_BP_MERGE)) {
            tr_msgf(msg, msglen, "loads[%d] s = %g m must lie in [0, L = %g]", i, row[TR_LD_S],
                    m->L);
            return TR_EINVAL;
        }
        memcpy(m->load + TR_LD_NCOL * i, row, TR_LD_NCOL * sizeof(double));
        if (m->load[TR_LD_NCOL * i] > m->L) m->load[TR_LD_NCOL * i] = m->L;
    }
    return TR_OK;
}

/* Point-load sums at the breakpoints, world frame, from m->load. */
void tr_sum_breakpoint_loads(tr_model *m)
{
    int i, c;
    memset(m->bpF, 0, (size_t)3 * (m->nseg + 1) * sizeof(double));
    memset(m->bpM, 0, (size_t)3 * (m->nseg + 1) * sizeof(double));
    for (i = 0; i < m->nl; i++) {
        const double *row = m->load + TR_LD_NCOL * i;
        const int b = find_bp(m, row[TR_LD_S]);
        for (c = 0; c < 3; c++) {
            m->bpF[3 * b + c] += row[TR_LD_F + c];
            m->bpM[3 * b + c] += row[TR_LD_M + c];
        }
    }
}

/* The partial distributed loads from the flat rows dloads (nd x 5) into m->dload;
 * TR_EINVAL with a message naming the row when a value is not finite or the interval
 * is not 0 <= s0 < s1 <= L. */
static int read_dloads(tr_model *m, const double *dloads, char *msg, size_t msglen)
{
    int i, c;
    for (i = 0; i < m->nd; i++) {
        const double *row = dloads + TR_DL_NCOL * i;
        for (c = 0; c < TR_DL_NCOL; c++)
            if (!isfinite(row[c])) {
                tr_msgf(msg, msglen, "dloads[%d][%d] = %g must be finite", i, c, row[c]);
                return TR_EINVAL;
            }
        if (!(row[TR_DL_S0] >= 0.0 && row[TR_DL_S0] < row[TR_DL_S1] &&
              row[TR_DL_S1] <= m->L * (1.0 + TR_BP_MERGE))) {
            tr_msgf(msg, msglen,
                    "dloads[%d] [s0, s1] = [%g, %g] m must satisfy 0 <= s0 < s1 <= L = %g", i,
                    row[TR_DL_S0], row[TR_DL_S1], m->L);
            return TR_EINVAL;
        }
        memcpy(m->dload + TR_DL_NCOL * i, row, TR_DL_NCOL * sizeof(double));
        if (m->dload[TR_DL_NCOL * i + TR_DL_S1] > m->L) m->dload[TR_DL_NCOL * i + TR_DL_S1] = m->L;
        for (c = 0; c < 3; c++)
            if (row[TR_DL_F + c] != 0.0) m->has_pdist = 1;
    }
    return TR_OK;
}

/* Partial distributed-force sums per segment, world frame, from m->dload: a load acts
 * on the segments between the breakpoints nearest its s0 and s1. */
static void sum_segment_dloads(tr_model *m)
{
    int i, k, c;
    memset(m->seg_pdist, 0, (size_t)3 * (m->nseg > 0 ? m->nseg : 1) * sizeof(double));
    for (i = 0; i < m->nd; i++) {
        const double *row = m->dload + TR_DL_NCOL * i;
        const int k0 = find_bp(m, row[TR_DL_S0]), k1 = find_bp(m, row[TR_DL_S1]);
        for (k = k0; k < k1; k++)
            for (c = 0; c < 3; c++) m->seg_pdist[3 * k + c] += row[TR_DL_F + c];
    }
}

/* Breakpoints: 0, L, the shooting nodes j L / M, tendon anchors, point loads and the
 * ends of the partial distributed loads (a zero load still makes one: compliance probes
 * need it), merged within TR_BP_MERGE L; then the per-breakpoint tables and the active
 * tendons per segment. */
static int place_breakpoints(tr_model *m)
{
    const int nt = m->nt, nl = m->nl;
    double *cand = (double *)malloc(
        (size_t)(nt + nl + 2 * m->nd + 2 + m->nshoot + m->nsec + 2 * m->nroute) * sizeof(double));
    int i, k, nc = 0, nb = 0, nact = 0;
    if (!cand) return TR_ENOMEM;
    cand[nc++] = 0.0;
    cand[nc++] = m->L;
    for (i = 1; i < m->nshoot; i++) cand[nc++] = m->L * ((double)i / m->nshoot);
    for (i = 0; i < nt; i++) cand[nc++] = m->tendon[i].t;
    for (i = 0; i < nl; i++) cand[nc++] = m->load[TR_LD_NCOL * i + TR_LD_S];
    for (i = 0; i < 2 * m->nd; i++) cand[nc++] = m->dload[TR_DL_NCOL * (i / 2) + i % 2];
    for (i = 0; i < m->nsec; i++) cand[nc++] = m->sec[TR_SC_NCOL * i + TR_SC_END];
    for (i = 0; i < m->nroute; i++)
        if (m->route[TR_RT_NCOL * i + TR_RT_KIND] == TR_ROUTE_PIECE) {
            cand[nc++] = m->route[TR_RT_NCOL * i + TR_RT_S0];
            cand[nc++] = m->route[TR_RT_NCOL * i + TR_RT_S1];
        }
    qsort(cand, nc, sizeof(double), cmp_double);
    m->bp = (double *)malloc((size_t)nc * sizeof(double));
    if (!m->bp) {
        free(cand);
        return TR_ENOMEM;
    }
    for (i = 0; i < nc; i++) {
        if (nb > 0 && cand[i] - m->bp[nb - 1] <= TR_BP_MERGE * m->L) continue;
        m->bp[nb++] = cand[i];
    }
    free(cand);
    /* snap the last to L exactly */
    if (m->L - m->bp[nb - 1] <= TR_BP_MERGE * m->L) m->bp[nb - 1] = m->L;
    m->nseg = nb - 1;
    m->bpF = (double *)calloc((size_t)3 * (m->nseg + 1), sizeof(double));
    m->bpM = (double *)calloc((size_t)3 * (m->nseg + 1), sizeof(double));
    m->seg_act_start = (int *)calloc((size_t)m->nseg + 1, sizeof(int));
    m->seg_act = (int *)calloc((size_t)(nt > 0 ? nt * m->nseg : 1), sizeof(int));
    m->bp_node = (int *)calloc((size_t)m->nseg + 1, sizeof(int));
    m->bp_jump = (int *)calloc((size_t)m->nseg + 1, sizeof(int));
    m->seg_pdist = (double *)calloc((size_t)3 * (m->nseg > 0 ? m->nseg : 1), sizeof(double));
    m->seg_rod = (double *)calloc((size_t)TR_SR_NCOL * (m->nseg > 0 ? m->nseg : 1), sizeof(double));
    if (!m->bpF || !m->bpM || !m->seg_act_start || !m->seg_act || !m->bp_node || !m->bp_jump ||
        !m->seg_pdist || !m->seg_rod)
        return TR_ENOMEM;
    /* a section joint changes the strains under the same force and moment: the taut
     * tendons kink there (the implicit jump) */
    for (i = 0; i + 1 < m->nsec; i++)
        m->bp_jump[find_bp(m, m->sec[TR_SC_NCOL * i + TR_SC_END])] = 1;
    /* a piecewise path may kink at its knots (straight pieces between disks) */
    for (i = 0; i < m->nroute; i++)
        if (m->route[TR_RT_NCOL * i + TR_RT_KIND] == TR_ROUTE_PIECE)
            m->bp_jump[find_bp(m, m->route[TR_RT_NCOL * i + TR_RT_S1])] = 1;
    tr_fill_segment_rods(m);
    for (i = 1; i < m->nshoot; i++) m->bp_node[find_bp(m, m->L * ((double)i / m->nshoot))] = i;
    for (i = 0; i < nt; i++) m->bp_jump[find_bp(m, m->tendon[i].t)] = 1;
    for (i = 0; i < nl; i++) m->bp_jump[find_bp(m, m->load[TR_LD_NCOL * i + TR_LD_S])] = 1;
    for (i = 0; i < nt; i++) {
        m->tendon[i].end_bp = find_bp(m, m->tendon[i].t);
        m->tendon[i].t = m->bp[m->tendon[i].end_bp];
    }
    tr_sum_breakpoint_loads(m);
    sum_segment_dloads(m);
    for (k = 0; k < m->nseg; k++) {
        m->seg_act_start[k] = nact;
        for (i = 0; i < nt; i++)
            if (m->tendon[i].end_bp > k) m->seg_act[nact++] = i;
    }
    m->seg_act_start[m->nseg] = nact;
    return TR_OK;
}

int tr_is_planar(const double *tendons, int nt, const double *loads, int nl, const double dist[3])
{
    int i;
    for (i = 0; i < nt; i++)
        if (fabs(sin(tendons[TR_TD_NCOL * i + TR_TD_ANGLE])) > TR_PLANAR_SIN) return 0;
    for (i = 0; i < nl; i++) {
        const double *row = loads + TR_LD_NCOL * i;
        if (row[TR_LD_F + 1] != 0.0 || row[TR_LD_M] != 0.0 || row[TR_LD_M + 2] != 0.0) return 0;
    }
    return dist[1] == 0.0;
}

int tr_is_planar_dist(const double *tendons, int nt, const double *loads, int nl,
                      const double dist[3], const double *dloads, int nd)
{
    int i;
    for (i = 0; i < nd; i++)
        if (dloads[TR_DL_NCOL * i + TR_DL_F + 1] != 0.0) return 0;
    return tr_is_planar(tendons, nt, loads, nl, dist);
}

/* The formulation (planar tendons get exactly cos phi = +-1, sin phi = 0), the
 * counts of unknowns and states, and the scales. */
static void formulate(tr_model *m, int planar, int ndisp, double rmax)
{
    int i;
    m->planar = planar;
    if (planar)
        for (i = 0; i < m->nt; i++) {
            tr_tendon *t = &m->tendon[i];
            t->cphi = t->cphi > 0.0 ? 1.0 : -1.0;
            t->sphi = 0.0;
            tr_tendon_base_frame_straight(t);
            if (m->precurved) tr_tendon_base_frame(m, i);
            t->t0[1] = 0.0;
            t->rt0[0] = 0.0;
        }
    m->ndisp = ndisp;
    m->n_base = m->planar ? 6 : 18;
    m->n_states = m->n_base + ndisp;
    m->n_unknowns = tr_n_force(m) + ndisp + (m->nshoot - 1) * m->n_states;
    m->n_states_rec = m->n_base + m->nt;
    m->n_stretch = 0;
    for (i = 0; i < m->nt; i++)
        if (m->tendon[i].control == TR_DISPLACEMENT && isfinite(m->tendon[i].EA)) m->n_stretch++;
    m->rhs_work = tr_rhs_work(m);
    m->F_s = m->EI / (m->L * m->L);
    m->M_s = m->EI / m->L;
    m->tau_s = rmax > 0.0 ? m->EI / (rmax * m->L) : m->F_s;
    m->len_s = rmax > 0.0 ? rmax : m->L;
    for (i = 0; i < 18; i++) m->xstate_scale[i] = 1.0;
    if (m->planar) {
        m->xstate_scale[TR_YP_X] = m->xstate_scale[TR_YP_Z] = m->L;
        m->xstate_scale[TR_YP_N1] = m->xstate_scale[TR_YP_N3] = m->F_s;
        m->xstate_scale[TR_YP_M] = m->M_s;
    } else {
        for (i = 0; i < 3; i++) {
            m->xstate_scale[TR_Y_P + i] = m->L;
            m->xstate_scale[TR_Y_N + i] = m->F_s;
            m->xstate_scale[TR_Y_M + i] = m->M_s;
        }
    }
}

int tr_model_alloc(tr_model **out, const double rod[6], const double *tendons, int nt,
                   const double *loads, int nl, const double dist[3], const tr_options *opt,
                   char *msg, size_t msglen)
{
    return tr_model_alloc_dist(out, rod, tendons, nt, loads, nl, dist, NULL, 0, opt, msg, msglen);
}

int tr_model_alloc_dist(tr_model **out, const double rod[6], const double *tendons, int nt,
                        const double *loads, int nl, const double dist[3], const double *dloads,
                        int nd, const tr_options *opt, char *msg, size_t msglen)
{
    return tr_model_alloc_ext(out, rod, tendons, nt, loads, nl, dist, dloads, nd, NULL, 0, NULL, 0,
                              opt, msg, msglen);
}

int tr_model_alloc_ext(tr_model **out, const double rod[6], const double *tendons, int nt,
                       const double *loads, int nl, const double dist[3], const double *dloads,
                       int nd, const double *sections, int nsec, const double *routes, int nroute,
                       const tr_options *opt, char *msg, size_t msglen)
{
    tr_model *m = NULL;
    int i, status, ndisp = 0;
    double rmax = 0.0;

    *out = NULL;
    if (msg && msglen) msg[0] = '\0';
    if (nt < 0 || nl < 0 || nd < 0 || nsec < 0 || (nt > 0 && !tendons) || (nl > 0 && !loads) ||
        (nd > 0 && !dloads) || (nsec > 0 && !sections) || nroute < 0 || (nroute > 0 && !routes) ||
        !rod || !dist || !opt) {
        tr_msgf(msg, msglen, "invalid arguments to tr_model_alloc (negative count or NULL array)");
        return TR_EINVAL;
    }
    if (check_rod(rod, msg, msglen) != TR_OK) return TR_EINVAL;
    for (i = 0; i < 3; i++)
        if (!isfinite(dist[i])) {
            tr_msgf(msg, msglen, "dist[%d] = %g must be finite", i, dist[i]);
            return TR_EINVAL;
        }
    if (opt->shooting_segments < 1 || opt->shooting_segments > TR_MAX_SHOOTING_SEGMENTS) {
        tr_msgf(msg, msglen, "shooting_segments = %d must lie in [1, %d]", opt->shooting_segments,
                TR_MAX_SHOOTING_SEGMENTS);
        return TR_EINVAL;
    }
    m = (tr_model *)calloc(1, sizeof *m);
    if (!m) goto nomem;
    m->L = rod[TR_ROD_L];
    m->EI = rod[TR_ROD_EI];
    m->GJ = rod[TR_ROD_GJ];
    m->EA = rod[TR_ROD_EA];
    m->GA = rod[TR_ROD_GA];
    m->kirchhoff = rod[TR_ROD_KIRCHHOFF] != 0.0;
    m->nt = nt;
    m->nl = nl;
    m->nshoot = opt->shooting_segments;
    m->tendon = (tr_tendon *)calloc(nt > 0 ? nt : 1, sizeof(tr_tendon));
    m->load = (double *)calloc(nl > 0 ? TR_LD_NCOL * nl : 1, sizeof(double));
    m->nd = nd;
    m->dload = (double *)calloc(nd > 0 ? TR_DL_NCOL * nd : 1, sizeof(double));
    m->sec = (double *)calloc(nsec > 0 ? TR_SC_NCOL * nsec : 1, sizeof(double));
    m->route = (double *)calloc(nroute > 0 ? TR_RT_NCOL * nroute : 1, sizeof(double));
    if (!m->tendon || !m->load || !m->dload || !m->sec || !m->route) goto nomem;
    status = tr_read_sections(m, sections, nsec, msg, msglen);
    if (status != TR_OK) goto fail;
    for (i = 0; i < nt; i++) {
        status = read_tendon(m, i, tendons + TR_TD_NCOL * i, &rmax, msg, msglen);
        if (status != TR_OK) goto fail;
        m->tendon[i].target_row = -1;
        m->tendon[i].fric_index = -1;
        m->tendon[i].slide = 1;
        if (m->tendon[i].control == TR_DISPLACEMENT) {
            m->tendon[i].gamma_index = m->tendon[i].len_index = ndisp++;
        } else {
            m->tendon[i].gamma_index = m->tendon[i].len_index = -1;
        }
    }
    status = tr_read_routes(m, routes, nroute, msg, msglen);
    if (status != TR_OK) goto fail;
    status = read_loads(m, loads, msg, msglen);
    if (status == TR_OK) status = read_dloads(m, dloads, msg, msglen);
    if (status != TR_OK) goto fail;
    memcpy(m->dist, dist, 3 * sizeof(double));
    m->has_dist = (dist[0] != 0.0 || dist[1] != 0.0 || dist[2] != 0.0);
    /* tensile loads: multiple shooting where single shooting's sensitivities would grow
     * too fast (tr_options.c) */
    m->shoot_growth = tr_shooting_growth(m);
    if (opt->auto_shooting && m->nshoot == 1) {
        m->nshoot = tr_auto_segments(m->shoot_growth);
        m->shoot_auto = m->nshoot > 1;
    }
    if (place_breakpoints(m) != TR_OK) goto nomem;
    if (tr_route_pieces(m) != TR_OK) goto nomem;
    if (m->precurved || m->n_routed > 0)
        for (i = 0; i < nt; i++) tr_tendon_base_frame(m, i);
    formulate(m,
              !opt->force_spatial &&
                  tr_is_planar_dist(tendons, nt, m->load, nl, dist, m->dload, nd) &&
                  tr_sections_planar(m->sec, m->nsec) && m->n_routed == 0,
              ndisp, rmax);
    status = tr_check_routing(m, msg, msglen);
    if (status != TR_OK) goto fail;

    status = tr_rest_lengths(m, m->scene_message, sizeof m->scene_message);
    if (status == TR_OK)
        status = tr_check_indeterminate(m, m->scene_message, sizeof m->scene_message);
    if (status == TR_EINVAL || status == TR_ENOMEM) {
        tr_msgf(msg, msglen, "%s", m->scene_message);
        goto fail;
    }
    m->scene_status = status;
    *out = m;
    return TR_OK;
nomem:
    status = TR_ENOMEM;
    tr_msgf(msg, msglen, "out of memory while compiling the model");
fail:
    tr_model_free(m);
    return status;
}

/* malloc'd copy of n elements of size sz (at least one element), or NULL. */
static void *dup_array(const void *src, size_t n, size_t sz)
{
    void *p = malloc((n > 0 ? n : 1) * sz);
    if (p && n > 0) memcpy(p, src, n * sz);
    return p;
}

tr_model *tr_model_clone(const tr_model *m)
{
    tr_model *c;
    size_t nb;
    if (!m) return NULL;
    nb = (size_t)m->nseg + 1;
    c = (tr_model *)malloc(sizeof *c);
    if (!c) return NULL;
    *c = *m;
    c->tendon = (tr_tendon *)dup_array(m->tendon, (size_t)m->nt, sizeof(tr_tendon));
    c->load = (double *)dup_array(m->load, (size_t)TR_LD_NCOL * m->nl, sizeof(double));
    c->bp = (double *)dup_array(m->bp, nb, sizeof(double));
    c->bpF = (double *)dup_array(m->bpF, 3 * nb, sizeof(double));
    c->bpM = (double *)dup_array(m->bpM, 3 * nb, sizeof(double));
    c->seg_act_start = (int *)dup_array(m->seg_act_start, nb, sizeof(int));
    c->seg_act = (int *)dup_array(m->seg_act, (size_t)m->nt * m->nseg, sizeof(int));
    c->bp_node = (int *)dup_array(m->bp_node, nb, sizeof(int));
    c->bp_jump = (int *)dup_array(m->bp_jump, nb, sizeof(int));
    c->dload = (double *)dup_array(m->dload, (size_t)TR_DL_NCOL * m->nd, sizeof(double));
    c->seg_pdist = (double *)dup_array(m->seg_pdist, (size_t)3 * m->nseg, sizeof(double));
    c->sec = (double *)dup_array(m->sec, (size_t)TR_SC_NCOL * m->nsec, sizeof(double));
    c->seg_rod = (double *)dup_array(m->seg_rod, (size_t)TR_SR_NCOL * m->nseg, sizeof(double));
    c->route = (double *)dup_array(m->route, (size_t)TR_RT_NCOL * m->nroute, sizeof(double));
    c->seg_piece =
        m->seg_piece ? (int *)dup_array(m->seg_piece, (size_t)m->nseg * m->nt, sizeof(int)) : NULL;
    if ((m->seg_piece && !c->seg_piece) || !c->route || !c->sec || !c->seg_rod || !c->tendon ||
        !c->load || !c->bp || !c->bpF || !c->bpM || !c->seg_act_start || !c->seg_act ||
        !c->bp_node || !c->bp_jump || !c->dload || !c->seg_pdist) {
        tr_model_free(c);
        return NULL;
    }
    return c;
}

tr_model *tr_model_reshoot(const tr_model *m, const tr_options *opt, int nshoot, char *msg,
                           size_t msglen)
{
    double rod[TR_ROD_NCOL], *tendons, *row;
    tr_options o = *opt;
    tr_model *out = NULL;
    int i;
    tendons = (double *)malloc((size_t)(m->nt > 0 ? m->nt : 1) * TR_TD_NCOL * sizeof(double));
    if (!tendons) return NULL;
    rod[TR_ROD_L] = m->L;
    rod[TR_ROD_EI] = m->EI;
    rod[TR_ROD_GJ] = m->GJ;
    rod[TR_ROD_EA] = m->EA;
    rod[TR_ROD_GA] = m->GA;
    rod[TR_ROD_KIRCHHOFF] = m->kirchhoff;
    for (i = 0; i < m->nt; i++) {
        const tr_tendon *t = &m->tendon[i];
        row = tendons + TR_TD_NCOL * i;
        row[TR_TD_OFFSET] = t->b;
        row[TR_TD_ANGLE] = t->phi;
        row[TR_TD_SLOPE] = t->a;
        row[TR_TD_EA] = t->EA;
        row[TR_TD_END] = t->t;
        row[TR_TD_CONTROL] = t->control == TR_TENSION ? 1.0 : 0.0;
        row[TR_TD_VALUE] = t->value;
        row[TR_TD_PRETENSION] = t->pretension;
    }
    o.shooting_segments = nshoot;
    o.force_spatial = !m->planar;
    if (tr_model_alloc_ext(&out, rod, tendons, m->nt, m->load, m->nl, m->dist, m->dload, m->nd,
                           m->sec, m->nsec, m->route, m->nroute, &o, msg, msglen) != TR_OK)
        out = NULL;
    else if (m->nfric > 0)
        tr_friction_copy(out, m);
    free(tendons);
    return out;
}
