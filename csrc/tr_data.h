/*
 * tr_data.h -- the workspace of a model's solves, struct tr_data (opaque in tendonrod.h:
 * only the core's files see its fields; callers read it through the accessors).
 */
#ifndef TR_DATA_H
#define TR_DATA_H

#include <gsl/gsl_matrix.h>
#include <gsl/gsl_odeiv2.h>
#include <gsl/gsl_multiroots.h>

#include "tendonrod.h"

struct tr_stab_ws;

/* The workspace (opaque in tendonrod.h): every buffer and result of a model's solves. */
struct tr_data {
    const tr_model *model; /* the model this workspace was allocated for */
    /* inputs (tr_inputs.c): the values of this workspace's solves -- actuation,
     * pretensions and rest lengths, point and distributed loads, friction coefficients,
     * the target -- over the compiled model's structure, which stays constant */
    const tr_model *vm;   /* the model the solver reads: &in (or, for a workspace allocated
                              on another workspace's view, that view) */
    tr_model in;          /* the view: the compiled model's structure arrays (shared,
                              read-only), this workspace's value arrays */
    tr_tendon *in_tendon; /* (2 nt) the view's tendons; then their copy before a perturbation */
    tr_tendon *in_tendon_save;
    double *in_block; /* the view's value arrays, and a design perturbation's sections
                              and seg_rod (in_sec, in_seg_rod) */
    double *in_sec, *in_seg_rod;
    tr_model in_save; /* the view before a design perturbation */
    int in_perturbed; /* 1 while a design perturbation is applied (tr_inputs_perturb) */
    tr_options opt;   /* options of this workspace */
    int k;            /* number of unknowns */
    /* iteration */
    double *x, *f;        /* (k) scaled unknowns / residual */
    double *xt, *ft, *dx; /* (k) trial point, trial residual, step */
    double *xs, *xp, *fs; /* (k) continuation: unknowns at the stage start and at the
                              previous stage, residual at the stage start */
    double *J;            /* (k x k) scaled Jacobian, row-major */
    double *work;         /* (k) a right-hand side (condition number, compliance) */
    double *hyb_f;        /* (k) residual evaluated for GSL's hybrid Jacobian callback */
    int *switched;        /* (ndisp) a tendon switched between taut and slack in a step */
    double *LU;           /* (k x k) LU factors, row-major (tru_lu_factor) */
    int *piv;             /* (k) their row swaps */
    double fnorm;         /* max-norm of f */
    int have_J, J_fresh, J_refresh;
    int jac_method;  /* tr_jacobian_method in use (continuation: TR_JAC_NEWTON) */
    int steps_moved; /* 1 once the step verification ran: polish the residual below tol */
    /* evaluation context */
    double lam_act;     /* continuation: actuation (q, prescribed tau) scaled by it */
    double lam_load;    /* continuation: point and distributed loads scaled by it */
    double lam_fric;    /* continuation: the friction coefficients scaled by it */
    double *tau, *beta; /* (nt) current tension [N] / slack [m] */
    int seg;            /* segment being integrated */
    int rec;            /* 1: recording layout (all path lengths) */
    int rec_coarse;     /* 1: a stability grid's recording (tr_record.c: RK4 steps of up to
                           TR_RECORD_COARSE_FRACTION of a shooting step, the tip checked) */
    int steps;          /* current total fixed steps */
    int steps_double;   /* 1: every segment takes twice its steps (step-doubling estimate) */
    int probe_bp;       /* breakpoint of the probe load of a linearisation, -1 none */
    double probe[6];    /* probe load (world F, M) added at probe_bp */
    double *capture;    /* NULL, or ((nseg + 1) x 12): an evaluation stores p (3) world [m],
                               R (9) row-major at each breakpoint b = 1..nseg in row b (the state
                               just proximal of the breakpoint's jump) -- a linearisation */
    /* integrator workspaces */
    double *y, *k1, *k2, *k3, *k4, *yt, *yerr; /* (n_states_rec) */
    double *ysave;  /* (n_states_rec) a saved end state (step verification, recording check) */
    double *x_of_y; /* (k) the unknowns of the last shooting evaluation whose end state is y */
    double *f_of_y; /* (k) its residual */
    double *x_J;    /* (k) the unknowns of this solve's last finite-difference Jacobian */
    int steps_J;    /* ... and its step count */
    int y_steps;    /* its step count; -1: y holds no such end state (recording, doubled
                       steps, a compliance probe, continuation) */
    gsl_odeiv2_system sys_shoot, sys_rec;
    gsl_odeiv2_step *rk8_shoot, *rk8_rec;
    gsl_odeiv2_step *ad_step_shoot, *ad_step_rec;
    gsl_odeiv2_control *ad_ctl_shoot, *ad_ctl_rec;
    gsl_odeiv2_evolve *ad_ev_shoot, *ad_ev_rec;
    /* cold guess: the small-deflection linear model over the displacement-controlled
     * tendons, sum_j C_ij tau_j = rhs_i, solved on an active set */
    double *lin_C;   /* (ndisp x ndisp) compliance C_ij [m/N] */
    double *lin_A;   /* (ndisp x ndisp) C restricted to the active set, factored in place */
    double *lin_rhs; /* (ndisp) right-hand side [m] */
    double *lin_sol; /* (ndisp) tension change over the pretension [N] */
    double *lin_pre; /* (ndisp) pretension [N] */
    double *lin_tmp; /* (ndisp) scatter buffer */
    int *lin_act;    /* (ndisp) 1: taut (in the active set) */
    int *lin_map;    /* (ndisp) active-set index -> tendon gamma index */
    double *bp_pose; /* ((nseg + 1) x 12) p, R at each breakpoint (cold-start shape pass) */
    gsl_multiroot_fdfsolver *hyb; /* hybridsj workspace (jacobian_method = TR_JAC_HYBRID) */
    /* linearisation (tr_linearize) */
    double *Yx;       /* (6 nseg x k) d(pose at the breakpoints)/d(unknowns) */
    double *lin_pose; /* (3 x (nseg + 1) x 12) poses at the breakpoints: the solution's,
                                and those of the two other points of a difference stencil */
    int *lin_side;    /* (nt) the side of its taut/slack switch a tendon's derivatives
                               take (tr_linearize's at_switch) */
    /* work budget and the caller's poll hook (tr_set_poll) */
    double spent;           /* work of this solve [units, see TR_DEFAULT_MAX_WORK] */
    int stop;               /* 0, or TR_EBUDGET / TR_EINTERRUPTED once a poll said stop */
    int finishing;          /* 1 while the final outputs are computed: beyond the budget */
    int (*poll)(void *ctx); /* called about every TR_POLL_INTERVAL; nonzero: stop */
    void *poll_ctx;         /* its argument */
    double t_start, t_poll; /* wall clock at the solve's start and at the hook's last call [s] */
    /* the last successful solve, for tr_solve_warm */
    double *x_last; /* (k) its scaled unknowns */
    double *J_last; /* (k x k) its Jacobian */
    int steps_last; /* its verified step count */
    int have_last;  /* 1 once a solve succeeded in this workspace */
    /* the step verification that vouches for the current step count (steps = 0): the
     * scaled unknowns it measured at, its truncation estimate and step count; and the
     * one of the last successful solve */
    double *x_ver, *x_ver_last;     /* (k) each */
    double *val_ver, *val_ver_last; /* (nt) each: the actuation values it was measured at */
    double est_ver, est_ver_last;
    int steps_ver, steps_ver_last;
    int have_ver, have_ver_last;
    int have_val_ver, have_val_ver_last; /* 1: val_ver is known */
    int ver_carried; /* 1: this solve's step count was vouched for by tr_verify_carried */
    /* the stable branch (tr_branch.c) */
    double lam_hom;            /* continuation from the guess: residual - (1 - lam_hom) f_guess */
    double lam_imp;            /* an imperfection at probe_bp, scaled by 1 - lam_imp */
    double *x_guess, *f_guess; /* (k) the unknowns this solve started from, their residual */
    double *x_alt;             /* (k) an unstable answer, kept while a stable one is sought */
    double tip_guess[3];       /* tip position at x_guess, world [m]; NaN: not known */
    int via_path;              /* 1: the answer came from a continuation */
    int direct_try;            /* 1: a cold start with large loads tried direct Newton and
                                  converged: the verdict decides if it stands (tr_branch) */
    int ramp_stable;           /* 1: a continuation stage must end stable (tr_ramp) */
    int cont_total;            /* continuation stages of the attempts before this one */
    int lu_sign;               /* sign of det J at the last tr_lu_factor (0: singular) */
    /* the verdict of the last successful solve, kept by a warm solve close to it */
    int carry_valid, carry_stable, carry_index, carry_det;
    int stab_kept;       /* 1: this solve's verdict was kept from the last one */
    double carry_gap;    /* no eigenvalue of the verdict within this of zero [EI/L] */
    double carry_margin; /* its margin [EI/L] (NaN: not computed) */
    double *carry_x;     /* (k) its scaled unknowns */
    double *carry_val;   /* (nt + 7 (nseg + 1) + 3) its actuation values, breakpoints, their
                           loads and the distributed force (scaled, tr_branch.c) */
    char carry_reason[256];
    /* the second formulation that confirms an equilibrium found off the load path,
     * allocated the first time a solve needs it */
    struct tr_model *confirm_m;
    struct tr_data *confirm_d;
    int is_confirm;   /* 1: this workspace confirms another's (no nested confirmation) */
    int nfev_confirm; /* evaluations spent confirming, added to nfev at the end */
    /* counters and results */
    int nit, nfev, njev, cont_steps;
    int status;
    char message[TR_MSGLEN];
    double residual_norm; /* final scaled residual max-norm */
    double jacobian_cond; /* 1-norm condition number of the final Jacobian */
    double truncation;    /* step-doubling estimate (scaled residual), NaN if not estimated */
    /* output (recording pass) */
    int nnode;            /* number of output nodes (1 when tip_only) */
    double *s;            /* (nnode) arc length [m] */
    double *pos;          /* (nnode x 3) position, world [m] */
    double *rot;          /* (nnode x 9) rotation body-to-world, row-major */
    double *force;        /* (nnode x 3) internal force, world [N] */
    double *moment;       /* (nnode x 3) internal moment, world [N m] */
    double *tension;      /* (nt) tension [N] (at the actuator) */
    double *node_tension; /* (nnode x nt) each tendon's tension at each node [N]: its tension
                             at the actuator, less its friction deficit there; 0 distal of
                             its anchor and where it is slack */
    double *node_rest;    /* (nnode x nt) a frictional tendon's rest (unstretched) length from
                             the base to each node [m], int |w| / (1 + tau/EA) ds: the
                             material coordinate of the tendon there; NaN for the others */
    double *tau_here;     /* (nt) scratch: the tensions at a state (tr_tensions_at) */
    double *fric_ws;      /* (TR_FRIC_NCOL nfric) scratch of the right-hand side */
    double *fric_g;       /* (9 nfric) each frictional tendon's normal load tau t^' (3, body,
                             [N/m], 0 where slack) at the last right-hand side, and two copies */
    double *ysw;          /* (2 n_states_rec) scratch of the steps that cross a kink of the
                             friction law (tr_integrate.c) */
    int *fric_done;       /* (nfric) scratch of the same */
    double *slack;        /* (nt) slack [m] */
    double *displacement; /* (nt) actuator displacement [m] */
    double tip[18];       /* tip state of the solution: p (3) world [m], R (9) body-to-world
                             row-major, internal force (3) [N] and moment (3) [N m], world */
    double tip_angle;     /* planar formulation: the tip tangent's angle from +z toward +x
                             [rad], unwrapped along s (the integrated theta); spatial: NaN */
    /* stability of the solution (tr_stability.c): stable 1 / 0 / -1 (not tested or
     * critical within the test's accuracy, stab_reason says which), the margin (the
     * smallest eigenvalue of the constrained second variation, scaled by EI/L) and the
     * number of negative modes */
    struct tr_stab_ws *stab;       /* its workspace, allocated the first time */
    struct tr_stab_ws *stab_quick; /* the quick test's */
    int stable, stab_index;
    double stability;
    double stab_gap; /* no eigenvalue within this of zero [EI/L] (0: not known) */
    char stab_reason[256];
    int stab_twin; /* channel friction: the frictionless twin's verdict at the state (1 / 0 /
                      -1 as stable; -1 also without friction) */
    double stab_twin_margin; /* its margin [EI/L] (NaN: none) */
    int stab_twin_index;     /* its negative modes (-1: none) */
    char branch_note[512];   /* how tr_branch reached a stable answer ("": it did not act) */
    /* the closest approach of a taut tendon to the centre of curvature (tr_watch.c) on
     * the state where a load path stalled: the smallest path-length rate |w| / |w_ref|,
     * the tendon, the arc length, its tension and the limit EI / r^2 there */
    double ea_scale;     /* the tendons' EA in the length residuals scaled by it (1; below 1 on the
                        way up from softer tendons, tr_solve.c) */
    double tol_override; /* > 0: the Newton layer's convergence tolerance in place of
                            opt.tol (the options are never written during a solve) */
    int shared_mode;     /* 1: Jacobians carry the shared tension direction of stiff tendon sets
                        from a difference of its own (tr_newton.c), and steps may grow with it */
    int watch_have, watch_tendon;
    double watch_rate, watch_s, watch_tau, watch_limit, watch_act, watch_load;
    int lazy;        /* 1: tr_solve fills only the tip, tensions and slacks (and the
                             displacement of displacement-controlled tendons; NaN for the
                             others); the node arrays stay untouched until tr_record_from */
    int polish_once; /* 1: a converged solve takes one more Newton step whatever its size
                        (kept unless it raises the residual), so that a change of the values
                        too small to lift the residual above tol still moves the state */
    /* dynamics (tr_dyn.c): a time step's context, read by the spatial right-hand side
     * (inertia, damping, the history at each stage point); NULL for every static solve */
    struct tr_dyn_ctx *dyn;
    /* TR_ALLOC_CALLS: room for the buffers of the largest tr_path or tr_actuate call of the
     * model (tr_data_take); calls_used bytes of it taken */
    double *calls;
    size_t calls_len, calls_used;
};

/* tr_data.c: the buffers of a tr_path or tr_actuate call (TR_ALLOC_CALLS).  The workspace
 * reserves room for the largest call its model admits, and a call takes its buffers from
 * there.  tr_data_take: `bytes` zeroed bytes (as calloc gives them, 16-byte aligned) from
 * the reserve where they fit, else calloc'd (NULL: out of memory); tr_data_drop gives them
 * back (frees a calloc'd block), in any order.  The sizes, in doubles (ints for *ilen), of
 * a path's buffers (tr_path.c), an actuation run's (tr_act_run.c; n controls, mt target
 * components) and an actuation iterate's (tr_act_iter.c, the sum of its table of buffers):
 * the path and the run take their buffers by them, the workspace sizes its reserve by all
 * three (csrc/tests/alloc_count.c's pose actuation is that largest call: every tendon a
 * control, 6 components). */
void *tr_data_take(tr_data *d, size_t bytes);
void tr_data_drop(tr_data *d, void *p);
size_t tr_path_len(int nt, int nl, int k);
size_t tr_act_run_len(int nt, int k, int n, int mt);
size_t tr_act_iter_len(int nt, int n, int mt, size_t *ilen);
/* Converged states an actuation run keeps (the current iterate, the last few solves, the
 * trials a step holds). */
#define ACT_POOL 16

#endif /* TR_DATA_H */
