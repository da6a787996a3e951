/* Internal state of a simulation handle. */
#ifndef SPHSOLID_SIM_H
#define SPHSOLID_SIM_H

#include <stddef.h>
#include <stdint.h>

#include "effects/effects.h"
#include "sphsolid.h"

#define SPH_ERRMSG_SIZE 512
#define SPH_NAME_SIZE   64

typedef struct material {
    double K, mu, rho0;
    double c0_squared, c0, c_p;
    double weibull_k, weibull_m; /* flaws per volume [m^-3] and exponent
                                    (effect damage); k = 0: no flaws */
} material;

typedef struct body {
    char name[SPH_NAME_SIZE];
    int material;
    sph_motion motion;
    double vector[3]; /* velocity, applied force or angular velocity */
    double centre[3]; /* centre of a prescribed rotation */
    size_t first, count;
    double spacing;
    double total_mass;
    double extent_lo[3], extent_hi[3]; /* bounding box of the particles as
                                          added: files record it so a reader
                                          can tell bodies of another shape */
    double lo[3], hi[3];               /* extent of the body's lattice cells */
    double step[3];                    /* lattice step per axis (spacing if unknown) */
    double reaction[3];                /* prescribed bodies: the SPH force on them at the
                           last rate evaluation (sph_body_reaction) */
} body;

typedef struct probe {
    char name[SPH_NAME_SIZE];
    double point[3];
    /* particles within 2h + skin of the point when neighbour list number
     * near_list was built (0: none), in index order (probe.c) */
    int *near;
    size_t n_near, near_capacity;
    unsigned long near_list;
} probe;

/* Half neighbour list in CSR form: row a holds the particles b > a closer
 * than 2h + skin when built, and those b < a closer than that whose chunk
 * of the pair pass (`chunk` rows) is at least two before a's, sorted by
 * index (neighbour.c). */
typedef struct neighbour_list {
    uint32_t *offsets32; /* n + 1 row starts, when all fit in 32 bits */
    size_t *offsets;     /* n + 1 row starts otherwise (else NULL) */
    int *indices;
    size_t capacity; /* of indices */
    size_t n;        /* particles when built */
    size_t chunk;    /* rows per chunk of the pair pass when built */
    double skin;
    double displacement_bound; /* upper bound of any displacement since built */
    int valid;
} neighbour_list;

/* Pair terms a chunk of the rate engine adds after the pair pass: one
 * record of sums per target particle (rates.c). */
typedef struct far_list {
    size_t count, capacity; /* records */
    int record;             /* doubles per record that `terms` was sized for */
    int *target;
    double *terms;
    int failed;
} far_list;

struct output_file;

struct sph_sim {
    int dim, ncomp, nsym;
    int threads;
    int rate_path; /* RATE_PATH_*: the pair loop's instruction set (0: the widest) */
    int no_runs;   /* 1: the pair loop gathers pair by pair, no runs (tests) */
    char errmsg[SPH_ERRMSG_SIZE];

    /* model */
    int kernel;
    double h_over_dx;
    double h;            /* 0 until the first body fixes it */
    double dx_ref;       /* first body's spacing */
    double platen_inset; /* sph_set_platen_inset: platens laid this many
                            lattice steps closer to their body (0: none) */
    material *materials;
    int n_materials;
    effects fx;
    int has_domain;
    double lo[3], hi[3];
    int periodic[3];

    /* bodies and particles */
    body *bodies;
    int n_bodies;
    probe *probes;
    int n_probes;
    int probe_outside_nan; /* sph_set_probe_outside */
    size_t n, capacity;
    double *x, *v, *rho, *S, *mass;
    int *material_of; /* per particle */
    int *body_of;     /* per particle */

    /* integration (integrator.h) */
    const struct integrator *integ; /* NULL: the default, Improved Euler */
    double dt, t;
    int dt_set;
    long step;
    double *saved;    /* the integrator's state at the start of a step */
    size_t saved_per; /* doubles per particle in saved */
    double *x_saved;  /* positions at the start of the step, so that a
                               failed step can be undone */
    double *dv_dt, *drho_dt, *dS_dt, *dx_dt;
    int rates_valid;
    int carry_valid;                /* the rates carried by the integrator belong to */
    unsigned long long carry_print; /* the state with this fingerprint */
    neighbour_list nl;
    unsigned long nl_builds; /* neighbour lists built so far (run.c) */

    /* scratch of the rate engine, sized to scratch_n particles */
    size_t scratch_n;
    double *pair_data;       /* per particle: sigma/rho^2 and, unless every
                             material has the same, c0 (rates.c) */
    size_t pair_data_per;    /* doubles per particle allocated in pair_data */
    double *stress_R;        /* artificial stress, when on */
    double *sum_scratch;     /* pair sums without room in the rate arrays */
    size_t sum_scratch_n;    /* doubles */
    double *motion_scratch;  /* a caller's x and v, dim doubles apart */
    size_t motion_scratch_n; /* doubles */
    far_list *far;           /* one per chunk of the pair pass */
    size_t n_far;

    int allow_large; /* sph_set_allow_large: runs may take all available memory */

    /* watchdog: 0 switches a bound off */
    double watch_speed, watch_rho_min, watch_rho_max;

    /* failure report */
    int failed;
    long fail_step, fail_particle;
    int fail_body;
    const char *fail_quantity;

    /* progress */
    long progress_interval;
    sph_progress_fn progress;
    void *progress_user;

    /* effect damage (damage.c), NULL while off: per particle the damage
     * D, the weakest activation strain and the number of flaws */
    double *damage, *flaw_strain;
    int *flaw_count;
    size_t damage_n; /* particles the arrays were drawn for */

    /* energy account (sph_set_energy_account, energy.c): on, and the
     * totals since it was switched on: work of the prescribed motions and
     * applied forces, energy dissipated by damage, by the drucker_prager
     * return and by artificial viscosity [J; J/m in 2D]; the powers summed
     * over the rate evaluations of the current step; the powers of the last
     * evaluation, which open the next step of an integrator that carries
     * its rates (the leapfrog), while they belong to the rates it carries */
    int energy_account;
    double work_boundary, dissipated_damage, dissipated_plastic, dissipated_viscosity;
    double power_sum[2], power_last[2];
    int power_evals;
    double power_carry[2];
    int power_carry_valid;

    struct output_file *out;
};

/* error.c */
sph_status sph_fail(sph_sim *sim, sph_status status, const char *fmt, ...)
#ifdef __GNUC__
    __attribute__((format(printf, 3, 4)))
#endif
    ;
sph_status sph_ok(sph_sim *sim);
/* Characters of a caller's text that a message quotes (sph_clip). */
#define SPH_CLIP      40
#define SPH_CLIP_SIZE (SPH_CLIP + 40)
/* `text` for a message, in out[SPH_CLIP_SIZE]: as it is when it has at
 * most SPH_CLIP characters, else its first SPH_CLIP and "... (N
 * characters)"; control characters shown as '?'.  Returns out. */
const char *sph_clip(char *out, const char *text);
/* A public call's handle and one pointer it needs: SPH_ERR_ARGUMENT without
 * a handle, "fn: name is NULL" without the pointer, else SPH_OK. */
sph_status sph_need(sph_sim *sim, const void *p, const char *fn, const char *name);

/* materials.c */
/* Material `id` (*m) for the public call `fn`: sph_need's errors for its
 * argument `name` (p), then one naming the id if there is no such
 * material. */
sph_status material_of_call(sph_sim *sim, const char *fn, const char *name, const void *p, int id,
                            material **m);
/* The particles and neighbours of another code that a public call `fn`
 * takes, and its output `out` (named `out_name`): sph_need's errors for
 * the first of them that is NULL. */
sph_status caller_pairs(sph_sim *sim, const char *fn, const sph_particles *particles,
                        const sph_neighbours *neighbours, const void *out, const char *out_name);
/* The arrays of n particles a public call `fn` reads: SPH_ERR_ARGUMENT
 * without a handle; when n > 0, a message naming `names` if one of the
 * `count` arrays is NULL, then one naming the first particle whose index
 * in material_of (one of the arrays) is not a defined material. */
sph_status caller_arrays(sph_sim *sim, const char *fn, size_t n, const int *material_of,
                         const char *names, const void *const *arrays, int count);

/* The nearest periodic image of a separation component d along an axis of
 * length L (half = L / 2): the one shift the neighbour search, the rate
 * engine and the probes apply along a periodic axis. */
static inline double nearest_image(double d, double L, double half)
{
    return d > half ? d - L : d < -half ? d + L : d;
}

/* neighbour.c */
sph_status neighbour_build(sph_sim *sim);
/* Where row a of the list starts in its indices. */
static inline size_t neighbour_row(const neighbour_list *nl, size_t a)
{
    return nl->offsets32 ? nl->offsets32[a] : nl->offsets[a];
}
void neighbour_free(neighbour_list *nl);

/* rates.c */
typedef struct rate_call {
    size_t n_local, n_total;
    const double *x, *v, *rho, *S, *mass;
    size_t stride; /* of x and v */
    const int *material;
    const sph_neighbours *neighbours;
    const uint32_t *offsets32; /* row starts instead of neighbours->offsets */
    int periodic;              /* apply minimum image with sim's domain */
    double *dv_dt, *drho_dt, *dS_dt, *dx_dt;
    int half;             /* the list holds each pair once (else full) */
    int far_in_both_rows; /* a half list that also holds, in row a, every
                             local b < a at least two chunks of the pair
                             pass before a (neighbour.c) */
    double *partial;      /* if set: the pair pass only, its sums for all
                               n_total particles written here (ghosts too) */
    int pass;             /* PASS_*: the rates computed (0: all) */
    const double *damage; /* n_total, when effect damage is on (else NULL) */
    int sorted_rows;      /* each row's indices ascending, none repeated
                             (neighbour.c's lists; a caller's: tested) */
} rate_call;
enum {
    PASS_CONTINUITY = SPH_RATES_CONTINUITY, /* drho/dt, dS/dt, XSPH velocity */
    PASS_MOMENTUM = SPH_RATES_MOMENTUM,     /* dv/dt */
    PASS_ALL = SPH_RATES_ALL
};

/* Instruction-set paths of the pair loop (rates.c). */
enum {
    RATE_PATH_AUTO = 0,     /* the widest the CPU has */
    RATE_PATH_BASELINE = 1, /* the build's target (x86-64: SSE2) */
    RATE_PATH_AVX2 = 2,     /* x86-64-v3: AVX2 and FMA */
    RATE_PATH_AVX512 = 3    /* x86-64-v4: AVX-512 */
};
/* The path a call takes when `wanted` is asked for: `wanted` if the build
 * and the CPU have it, else the widest they have. */
int rates_path(int wanted);
/* The path the environment variable SPHSOLID_RATE_PATH asks for
 * (*path: RATE_PATH_AUTO when unset or empty), or an error naming its
 * value when it is not a path's name or the build or CPU lacks it. */
sph_status rates_path_from_environment(sph_sim *sim, int *path);

sph_status rates_run(sph_sim *sim, const rate_call *call);
/* The rates of the handle's own particles (periodic, its half list) into its
 * rate arrays. */
sph_status rates_of_handle(sph_sim *sim, int pass);
int sim_threads(const sph_sim *sim);
size_t rates_chunk_rows(int dim, size_t n);
size_t rates_far_bytes(const sph_sim *sim);
/* Whether each of the n_rows rows of a caller's list ascends without
 * repeats (the pair pass then takes runs of consecutive neighbours), on
 * `threads` threads for a long list. */
int rates_rows_ascending(size_t n_rows, const sph_neighbours *nb, int threads);

/* bodies.c (sim_support, sim_shrink_to_fit, rotation_velocity); run.c (sim_prepare) */
double sim_support(const sph_sim *sim);
sph_status sim_prepare(sph_sim *sim);
void sim_shrink_to_fit(sph_sim *sim);
void rotation_velocity(int dim, const double *omega, const double *centre, const double *x,
                       double *v);

/* geometry.c */
void body_extent_from_particles(sph_sim *sim, int id);
void body_set_lattice(sph_sim *sim, int id, const double lo[3], const double hi[3],
                      const double step[3]);
/* Add a body of count[0] x count[1] x count[2] (1 in 2D) particles at the centres of
 * the cells of `step` from `lo`, each with its cell's volume, and record its
 * lattice; `what` names the body's kind in a memory failure. */
sph_status lattice_add(sph_sim *sim, const char *name, int material, const double lo[3],
                       const double hi[3], const long count[3], const double step[3],
                       double spacing, const char *what, int *id);

/* effects.c */
sph_status effects_set(sph_sim *sim, const char *name, const char *parameters);
sph_status effects_off(sph_sim *sim, const char *name);
int effects_is_on(const effects *fx, const char *name);
void effects_describe(const effects *fx, char *buf, size_t size);
/* Whether effect `effect` (registry index, sph_effect_info_get) is on in
 * fx; its parameters' values (in registry order, at most
 * EFFECTS_MAX_PARAMETERS) into `values`. */
#define EFFECTS_MAX_PARAMETERS 8
int effects_values(const effects *fx, int effect, double *values);

/* damage.c */
/* Draws the flaws of particles not drawn yet (damage on), or frees the
 * arrays (damage off). */
sph_status damage_prepare(sph_sim *sim);
/* Activation and growth over a step of dt at the current state; *changed
 * is set when some D grew. */
sph_status damage_stage(sph_sim *sim, double dt, int *changed);
void damage_free(sph_sim *sim);
/* Flaws of particle a active at its current largest principal strain. */
int damage_active_flaws(const sph_sim *sim, size_t a);
/* Draws every particle's flaws again (seed, flaws or a material changed). */
void damage_redraw(sph_sim *sim);
/* Fragment id of each particle (connected regions of free-body particles
 * with D < 1 within the kernel support; -1 elsewhere), and their number. */
sph_status damage_fragments(sph_sim *sim, double *out, long *count);

/* plasticity.c */
/* The drucker_prager return of every free-body particle at the current
 * state; *changed is set when some deviator was scaled. */
sph_status plastic_stage(sph_sim *sim, int *changed);

/* energy.c (the energy account) */
/* Adds the boundary power and the viscous dissipation rate of the current
 * rate evaluation (called before the prescribed accelerations are zeroed). */
void energy_account_evaluation(sph_sim *sim);
/* Opens a step's sum of powers: empty, or with `carried` (the step starts
 * from rates it does not evaluate again) the powers of the evaluation that
 * gave them, if the handle has them. */
void energy_account_open(sph_sim *sim, int carried);
/* Integrates the step's powers over dt. */
void energy_account_step(sph_sim *sim, double dt);
/* The elastic energy particle a releases when its damage grows from
 * D_before to D_after at its current state. */
double energy_damage_released(const sph_sim *sim, size_t a, double D_before, double D_after);

/* probe.c */
sph_status probe_sample_point(sph_sim *sim, probe *p, double *values, int in_run);
void probes_free(sph_sim *sim);

/* validate.c */
/* Coordinates are limited to SPH_COORDINATE_LIMIT spacings from the origin
 * (|x| <= limit * spacing): a double then rounds a position to at most
 * 2.2e-10 of a spacing.  coordinate_check fails naming the body, the
 * particle (index in its body) and the value. */
#define SPH_COORDINATE_LIMIT 1e6
sph_status coordinate_check(sph_sim *sim, const char *body_name, size_t particle, int axis,
                            double x, double spacing);
/* Positions within the coordinate limit, density and mass finite and
 * positive: the state a run may start from. */
sph_status state_check(sph_sim *sim);
/* The share of the available memory a run may take unless
 * sph_set_allow_large() lifts the limit to all of it. */
#define SPH_LARGE_FRACTION 0.5
/* SPH_ERR_MEMORY naming `what`, the bytes needed and available when
 * `particles` more particles would not fit in memory during a run. */
sph_status memory_check(sph_sim *sim, double particles, const char *what);

/* io_output.c */
sph_status output_write_due(sph_sim *sim);
void output_free(sph_sim *sim);

/* Row `a` of a caller's neighbour lists (sph_neighbours: CSR offsets and
 * indices when `by_rows`, else per-particle lists and counts). */
static inline const int *caller_row(const sph_neighbours *nb, int by_rows, size_t a, size_t *length)
{
    if (by_rows) {
        *length = nb->offsets[a + 1] - nb->offsets[a];
        return nb->indices + nb->offsets[a];
    }
    *length = (size_t)nb->counts[a];
    return nb->lists[a];
}

#endif
