/* The engine's step loop in C: what Engine.step does per step, without the Python in between.
 *
 * Part of the adapter (asperity2d/engine). Each step: set the slider's force (the constant drive
 * or the drive spring), cpSpaceStep, read every body into the row buffer, put the tracked bodies
 * back on their tracks if they drifted, read every contact and update the stick/slip switch.
 * The same C functions of Chipmunk and pymunk's batch module are called as the Python loop calls
 * (their addresses are handed in: nothing here links against pymunk), and the arithmetic is the
 * Python loop's, operation for operation, in IEEE double with no contraction into fused
 * multiply-adds (setup.py compiles with -ffp-contract=off): the results are bit-identical, which
 * tests/test_engine_kernel.py checks against the Python loop. asperity2d/engine/kernel.py loads
 * this file with cffi and mirrors the structs below in its cdef.
 *
 * It is an optional extension (a machine without a compiler installs without it and the Python
 * loop runs); the module init below only makes the file importable like any extension.
 */
#include <Python.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

typedef struct { double x, y; } asp_vect; /* cpVect */
typedef struct { int num, max; double *arr; } asp_float_array; /* pymunk's pmFloatArray */
typedef struct { int num, max; uintptr_t *arr; } asp_int_array; /* pymunk's pmIntArray */

typedef void (*space_step_fn)(void *space, double dt);
typedef void (*set_force_fn)(void *body, asp_vect force);
typedef void (*each_fn)(void *space, void *iterator, void *data);
typedef void (*set_friction_fn)(void *shape, double mu);

typedef struct {
    /* Chipmunk and pymunk: the space, the slider, the functions and the batch buffers */
    uintptr_t space, body;
    uintptr_t space_step, set_force, each_body, each_arbiter, set_friction;
    uintptr_t get_body, set_body, get_arbiter;
    uintptr_t body_data, arbiter_data; /* pmBatchedData * */
    uintptr_t bodies, arbiter_ints, arbiter_floats; /* pmFloatArray *, pmIntArray *, pmFloatArray * */
    double *rows; /* the bodies' [x, y, vx, vy] rows (the buffer the body read writes) */
    /* the drive and the load (internal units) */
    int spring;
    double dt, k, c, v, origin, force, load;
    int64_t step_count;
    /* the tracks */
    int slider_row, lower_row0, n_lower, tracked, fixed_slider;
    double y_track, track_tolerance, max_drift;
    double *lower_x0;
    /* the contact law (StickSlip.law), its state one entry per lower asperity; law_kind: 0 the
     * static/kinetic switch, 1 velocity weakening, 2 viscous plus Coulomb, 3 rate-and-state
     * (kernel.py's C_LAWS); mu_idle: the law's coefficient of a contact not touching */
    int switch_active;
    double switch_dt, stick_speed, slip_distance, mu_static, mu_kinetic, mu_idle;
    int law_kind;
    double v_s, viscosity;
    double rs_a, rs_b, rs_d_c, rs_v_0, rs_mu_0, rs_dt; /* RateState's fields, internal units */
    uint8_t *stuck, *present;
    double *slid, *mu;
    double *theta; /* the rate-and-state law's state per lower asperity (NaN: not touching) */
    uintptr_t *shapes;
    uintptr_t slider_id;
    uintptr_t *ids; /* the lower bodies' ids, sorted ... */
    int32_t *id_index; /* ... and each one's lower asperity index */
    double *slips; /* scratch, n_lower */
    uint8_t *has; /* scratch, n_lower */
} asp_ctx;

static int lower_index(const asp_ctx *c, uintptr_t id)
{
    int lo = 0, hi = c->n_lower;
    while (lo < hi) {
        int mid = lo + (hi - lo) / 2;
        if (c->ids[mid] < id) lo = mid + 1;
        else hi = mid;
    }
    return (lo < c->n_lower && c->ids[lo] == id) ? c->id_index[lo] : -1;
}

/* Engine._project: the largest drift off a track (Python's max: the first of equal values), and
 * every tracked body put back when it is over the tolerance. */
static void project(asp_ctx *c)
{
    double *rows = c->rows;
    double drift = 0.0;
    if (c->tracked && c->n_lower > 0) {
        const double *x0 = c->lower_x0;
        const double *x = rows + 4 * c->lower_row0;
        drift = fabs(x[0] - x0[0]);
        for (int i = 1; i < c->n_lower; i++) {
            double d = fabs(x[4 * i] - x0[i]);
            if (d > drift) drift = d;
        }
    }
    if (c->fixed_slider) {
        double d = fabs(rows[4 * c->slider_row + 1] - c->y_track);
        if (d > drift) drift = d;
    }
    if (drift > c->max_drift) c->max_drift = drift;
    if (drift > c->track_tolerance) {
        if (c->tracked) {
            double *x = rows + 4 * c->lower_row0;
            for (int i = 0; i < c->n_lower; i++) {
                x[4 * i] = c->lower_x0[i];
                x[4 * i + 2] = 0.0;
            }
        }
        if (c->fixed_slider) {
            rows[4 * c->slider_row + 1] = c->y_track;
            rows[4 * c->slider_row + 3] = 0.0;
        }
        asp_float_array *arr = (asp_float_array *)c->bodies;
        int num = arr->num;
        arr->num = 0;
        ((each_fn)c->each_body)((void *)c->space, (void *)c->set_body, (void *)c->body_data);
        arr->num = num;
    }
}

/* ln 2 rounded to a double: contact_laws.py's _LN2, the same literal */
#define ASP_LN2 0.6931471805599453

/* RateState.coefficient: mu at slip speed v >= 0 and state theta, regularised at v = 0 (the
 * same libm calls as Python's math module makes -- log, exp, asinh, and expm1 in the step -- in
 * the same order) */
static double rate_state_mu(const asp_ctx *c, double v, double theta)
{
    if (v == 0) return 0.0;
    double x = log(v / (2.0 * c->rs_v_0)) + (c->rs_mu_0 + c->rs_b * log(c->rs_v_0 * theta / c->rs_d_c)) / c->rs_a;
    return c->rs_a * (x > 30.0 ? x + ASP_LN2 : asinh(exp(x)));
}

/* RateState.step for one contact: *theta its state, replaced by the new one (the ageing law solved
 * exactly over the step at the slip speed v >= 0; the reference state D_c / v_0 for a contact just
 * formed); returns the coefficient. Exported for tests/test_contact_laws.py, which holds it to the
 * Python reference over the branches a run seldom reaches (v = 0, the large-x form). */
double asp_rate_state_step(const asp_ctx *c, int is_new, double v, double *theta)
{
    double t;
    if (is_new) {
        t = c->rs_d_c / c->rs_v_0;
    } else if (v > 0) {
        double eps = v * c->rs_dt / c->rs_d_c;
        t = *theta * exp(-eps) - c->rs_d_c / v * expm1(-eps);
    } else {
        t = *theta + c->rs_dt;
    }
    *theta = t;
    return rate_state_mu(c, v, t);
}

/* StickSlip.update on the contacts just read: each touching lower asperity's slip speed (the
 * largest over the tips; its sign does not matter to the laws here), then the law. A lost contact
 * goes back to the law's initial state and its idle coefficient. */
static void stick_slip(asp_ctx *c)
{
    const asp_int_array *ia = (const asp_int_array *)c->arbiter_ints;
    const asp_float_array *fa = (const asp_float_array *)c->arbiter_floats;
    const uintptr_t *ints = ia->arr;
    const double *floats = fa->arr;
    int n = c->n_lower, any_present = 0;
    for (int i = 0; i < n; i++) any_present |= c->present[i];
    if (ia->num == 0 && !any_present) return;
    const double *rows = c->rows;
    double svx = rows[4 * c->slider_row + 2], svy = rows[4 * c->slider_row + 3];
    memset(c->has, 0, (size_t)n);
    for (int k = 0; k + 2 < ia->num; k += 3) {
        if (!ints[k + 2]) continue;
        int i = lower_index(c, ints[k] + ints[k + 1] - c->slider_id);
        if (i < 0) continue; /* the floor */
        double nx = floats[2 * k + 2], ny = floats[2 * k + 3];
        const double *r = rows + 4 * (c->lower_row0 + i);
        double slip = fabs((svx - r[2]) * ny - (svy - r[3]) * nx);
        double best = c->has[i] ? c->slips[i] : -1.0;
        if (slip > best) { /* a lower asperity may touch two tips; a NaN slip is not kept */
            c->slips[i] = slip;
            c->has[i] = 1;
        }
    }
    double v_stick = c->stick_speed, mu_s = c->mu_static, mu_k = c->mu_kinetic, mu_idle = c->mu_idle;
    set_friction_fn set_friction = (set_friction_fn)c->set_friction;
    for (int i = 0; i < n; i++) {
        if (!c->has[i]) {
            if (c->present[i]) { /* contact lost */
                c->stuck[i] = 0;
                c->slid[i] = 0.0;
                c->theta[i] = NAN;
                if (c->mu[i] != mu_idle) {
                    set_friction((void *)c->shapes[i], mu_idle);
                    c->mu[i] = mu_idle;
                }
            }
            continue;
        }
        double slip = c->slips[i];
        double mu;
        if (c->law_kind == 1) { /* VelocityWeakening.step */
            mu = mu_k + (mu_s - mu_k) * exp(-slip / c->v_s);
        } else if (c->law_kind == 2) { /* ViscousCoulomb.step */
            mu = mu_k + c->viscosity * slip;
        } else if (c->law_kind == 3) { /* RateState.step */
            mu = asp_rate_state_step(c, !c->present[i], slip, &c->theta[i]);
        } else { /* StaticKineticSwitch.step */
            if (!c->present[i]) { /* a new contact */
                c->stuck[i] = slip < v_stick;
                c->slid[i] = 0.0;
            } else if (c->stuck[i]) {
                if (slip > v_stick) {
                    c->slid[i] += slip * c->switch_dt;
                    if (c->slid[i] > c->slip_distance) c->stuck[i] = 0;
                } else {
                    c->slid[i] = 0.0;
                }
            } else if (slip < v_stick) {
                c->stuck[i] = 1;
                c->slid[i] = 0.0;
            }
            mu = c->stuck[i] ? mu_s : mu_k;
        }
        if (c->mu[i] != mu) {
            set_friction((void *)c->shapes[i], mu);
            c->mu[i] = mu;
        }
    }
    memcpy(c->present, c->has, (size_t)n);
}

/* Engine.step(n) without hooks: n steps. */
void asp_steps(asp_ctx *c, int64_t n)
{
    space_step_fn space_step = (space_step_fn)c->space_step;
    set_force_fn set_force = (set_force_fn)c->set_force;
    each_fn each_body = (each_fn)c->each_body, each_arbiter = (each_fn)c->each_arbiter;
    asp_float_array *bodies = (asp_float_array *)c->bodies;
    asp_int_array *ints = (asp_int_array *)c->arbiter_ints;
    asp_float_array *floats = (asp_float_array *)c->arbiter_floats;
    double *slider = c->rows + 4 * c->slider_row;
    double dt = c->dt;
    for (int64_t s = 0; s < n; s++) {
        asp_vect f;
        if (c->spring) {
            /* the spring at the position the step will end at (Engine.step's comment) */
            double x = slider[0], vx = slider[2];
            double x_d = c->origin + c->v * (double)(c->step_count + 1) * dt;
            f.x = c->k * (x_d - (x + vx * dt)) + c->c * (c->v - vx);
        } else {
            f.x = c->force;
        }
        f.y = -c->load;
        set_force((void *)c->body, f);
        space_step((void *)c->space, dt);
        bodies->num = 0;
        each_body((void *)c->space, (void *)c->get_body, (void *)c->body_data);
        c->step_count += 1;
        project(c);
        if (c->switch_active) {
            ints->num = 0;
            floats->num = 0;
            each_arbiter((void *)c->space, (void *)c->get_arbiter, (void *)c->arbiter_data);
            stick_slip(c);
        }
    }
}

/* kernel.py checks its cdef's layout of asp_ctx, and pymunk's of the structs mirrored at the top,
 * against this compiler's: 0 sizeof(asp_ctx), 1 offsetof(asp_ctx, has), 2 and 3 the array field's
 * offset in pmFloatArray and pmIntArray, 4 sizeof(cpVect), 5 sizeof(uintptr_t) */
size_t asp_layout(int which)
{
    switch (which) {
    case 0: return sizeof(asp_ctx);
    case 1: return offsetof(asp_ctx, has);
    case 2: return offsetof(asp_float_array, arr);
    case 3: return offsetof(asp_int_array, arr);
    case 4: return sizeof(asp_vect);
    case 5: return sizeof(uintptr_t);
    default: return 0;
    }
}

/* Engine.settle's steps (no switch, no step count): the drive spring's pull towards its far end
 * if there is one, plus ``push``. */
void asp_settle_steps(asp_ctx *c, int64_t n, double push)
{
    space_step_fn space_step = (space_step_fn)c->space_step;
    set_force_fn set_force = (set_force_fn)c->set_force;
    each_fn each_body = (each_fn)c->each_body;
    asp_float_array *bodies = (asp_float_array *)c->bodies;
    double *slider = c->rows + 4 * c->slider_row;
    for (int64_t s = 0; s < n; s++) {
        asp_vect f;
        double fx = c->spring ? c->k * (c->origin - slider[0]) : 0.0;
        f.x = fx + push;
        f.y = -c->load;
        set_force((void *)c->body, f);
        space_step((void *)c->space, c->dt);
        bodies->num = 0;
        each_body((void *)c->space, (void *)c->get_body, (void *)c->body_data);
        project(c);
    }
}

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_kernel",
                                    "The engine's step loop in C (loaded with cffi by kernel.py).", -1, NULL};

PyMODINIT_FUNC PyInit__kernel(void) { return PyModule_Create(&module); }
