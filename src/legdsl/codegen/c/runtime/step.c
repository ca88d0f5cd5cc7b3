/* step.c: legdsl's simulation step and run loop in C (the C backend's runtime).
 *
 * A line-by-line transliteration of the Python runtime, which stays the readable reference:
 *   actuators        legdsl/sim/actuators.py   (eqs. 1 and 5, saturation, their work)
 *   joint stops      legdsl/sim/simulate.py    Simulation.generalized_forces
 *   ground contact   legdsl/sim/contact.py     (four spring-dampers, anchors, eq. 6, slip, terrain)
 *   integrators      legdsl/sim/simulate.py    Simulation.step (semi-implicit Euler, RK4)
 *   recording        legdsl/sim/recorder.py    record_row, Simulation.energy
 *   the run loop     legdsl/sim/simulate.py    Simulation.run (record, check, step)
 * Every expression keeps the Python's operations in the Python's order (Python's min and max
 * are leg_min and leg_max, its sum() a left-to-right sum from 0.0, math.hypot and math.dist
 * CPython's vector_norm), so that the same inputs give the same doubles; the identity test
 * (tests/sim/test_c_backend.py) runs every shipped creature and controller on both backends
 * and compares every recorded array bit for bit, so any drift between the two fails CI.
 *
 * Where it reads part of a kinematic function's result (the rows of the feet that touch, the
 * root's pose), it calls the function's _some twin (dynamics_some.c, codegen/c/slices.py), which
 * writes those outputs as the whole function does and fails where the whole function fails.
 *
 * The creature comes in its sizes (legdsl_sizes.h, from the generated dynamics.h) and the
 * functions of legdsl_model.h, so one object of this file serves every creature of its sizes;
 * everything that varies per run is in the leg_sim struct (legdsl_sim.h).
 */
#include <stdint.h>
#include <float.h>
#include <math.h>

#include "legdsl_math.h"
#include "legdsl_sim.h"
#include "legdsl_sizes.h"
#include "legdsl_model.h"

#define LEG_DESCRIBE(type, name) #type " " #name ";"
const char leg_sim_fields[] = LEG_SIM_FIELDS(LEG_DESCRIBE);
int64_t leg_sim_size(void) { return (int64_t)sizeof(leg_sim); }
int64_t leg_sizes(int64_t *out) {
    out[0] = LEG_NQ; out[1] = LEG_NV; out[2] = LEG_NB; out[3] = LEG_NC;
    return 4;
}

/* This thread's table of sines and cosines (legdsl_math.h): runs of a batch go on in threads. */
static __thread leg_trig_entry trig_table[1 << LEG_TRIG_BITS];
leg_trig_entry *leg_trig_table(void) { return trig_table; }

#define NQ LEG_NQ
#define NV LEG_NV
#define NC LEG_NC
/* Scratch sizes that are never 0 (a creature without contacts still declares arrays). */
#define NC3 (3 * LEG_NC + 1)
#define NCJ (3 * LEG_NC * LEG_NV + 1)
#define NBP (12 * LEG_NB)
#define PY_TAU 6.283185307179586

/* ------------------------------------------------------------ CPython's vector_norm (3.11) */
static void dl_fast_sum(double a, double b, double *hi, double *lo) {
    double x = a + b;
    double z = x - a;
    *hi = x;
    *lo = b - z;
}

static void dl_mul(double x, double y, double *hi, double *lo) {
    double z = x * y;
    *hi = z;
    *lo = fma(x, y, -z); /* the exact rounding error of x * y */
}

static double vector_norm(int n, double *vec, double max, int found_nan) {
    double x, h, scale, csum = 1.0, frac1 = 0.0, frac2 = 0.0, hi, lo, shi, slo;
    int max_e;
    if (isinf(max)) return max;
    if (found_nan) return NAN;
    if (max == 0.0 || n <= 1) return max;
    frexp(max, &max_e);
    if (max_e < -1023) {
        for (int i = 0; i < n; i++) vec[i] /= DBL_MIN;
        return DBL_MIN * vector_norm(n, vec, max / DBL_MIN, found_nan);
    }
    scale = ldexp(1.0, -max_e);
    for (int i = 0; i < n; i++) {
        x = vec[i] * scale;
        dl_mul(x, x, &hi, &lo);
        dl_fast_sum(csum, hi, &shi, &slo);
        csum = shi;
        frac1 += lo;
        frac2 += slo;
    }
    h = sqrt(csum - 1.0 + (frac1 + frac2));
    dl_mul(-h, h, &hi, &lo);
    dl_fast_sum(csum, hi, &shi, &slo);
    csum = shi;
    frac1 += lo;
    frac2 += slo;
    x = csum - 1.0 + (frac1 + frac2);
    h += x / (2.0 * h);
    return h / scale;
}

/* math.hypot(x, y) */
double leg_hypot(double x, double y) {
    double vec[2] = {fabs(x), fabs(y)};
    double max = 0.0;
    int found_nan = 0;
    for (int i = 0; i < 2; i++) {
        found_nan |= isnan(vec[i]);
        if (vec[i] > max) max = vec[i];
    }
    return vector_norm(2, vec, max, found_nan);
}

/* math.dist(p, q) for 3-vectors */
double leg_dist3(const double *p, const double *q) {
    double vec[3];
    double max = 0.0;
    int found_nan = 0;
    for (int i = 0; i < 3; i++) {
        double x = fabs(p[i] - q[i]);
        vec[i] = x;
        found_nan |= isnan(x);
        if (x > max) max = x;
    }
    return vector_norm(3, vec, max, found_nan);
}

/* math.remainder(x, y): exact, as CPython's m_remainder; an infinite x is a domain error */
static double leg_remainder_e(double x, double y, int *err) {
    double r = remainder(x, y);
    if (isnan(r) && !isnan(x) && !isnan(y)) leg_flag(err, LEG_EDOM);
    return r;
}

static inline double dot3(const double *a, const double *b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* ------------------------------------------------------------ terrain (contact.py) */
static void surface(const leg_sim *s, double x, double y, double *o, double *n, int *err) {
    if (s->has_slope) {
        double a = s->slope_angle;
        o[0] = 0.0; o[1] = 0.0; o[2] = 0.0;
        n[0] = -leg_sin(a); n[1] = 0.0; n[2] = leg_cos(a);
        return;
    }
    double h = 0.0;
    for (int64_t k = 0; k < s->n_flats; k++) {
        const double *f = s->flats + 6 * k; /* x, x0, x1, y0, y1, height */
        int under = s->flat_is_box[k] ? (f[1] <= x && x <= f[2] && f[3] <= y && y <= f[4])
                                      : (x >= f[0]);
        if (under) h = leg_max(h, f[5]);
    }
    o[0] = x; o[1] = y; o[2] = h;
    n[0] = 0.0; n[1] = 0.0; n[2] = 1.0;
}

static double height(const leg_sim *s, double x, double y, int *err) {
    double o[3], n[3];
    surface(s, x, y, o, n, err);
    return o[2] - leg_div(n[0] * (x - o[0]) + n[1] * (y - o[1]), n[2]);
}

/* The terrain's height under (x, y), for the controller's sensors (machine.c). */
double leg_ground_height(const leg_sim *s, double x, double y, int *err) {
    return height(s, x, y, err);
}

static void tangents(const double *n, double *t1, double *t2) {
    t1[0] = n[2]; t1[1] = 0.0; t1[2] = -n[0];
    t2[0] = n[1] * t1[2] - n[2] * t1[1];
    t2[1] = n[2] * t1[0] - n[0] * t1[2];
    t2[2] = n[0] * t1[1] - n[1] * t1[0];
}

static double depth(const leg_sim *s, const double *p, double *n, int *err) {
    double o[3];
    surface(s, p[0], p[1], o, n, err);
    return n[0] * (o[0] - p[0]) + n[1] * (o[1] - p[1]) + n[2] * (o[2] - p[2]);
}

/* ------------------------------------------------------------ ground forces (contact.py) */
static double pad_force(const leg_sim *s, double dep, int *err) {
    double thickness = s->pad_thickness;
    double d = leg_min(dep, 0.9 * thickness);
    double f = s->normal_k * (leg_div(thickness, thickness - d) - 1.0);
    if (dep > d) {
        double slope = leg_div(s->normal_k * thickness, leg_pow(thickness - d, 2.0));
        f += slope * (dep - d);
    }
    return f;
}

static void ground_force(const leg_sim *s, int i, const double *p, const double *pv, double *out,
                         int *err) {
    out[0] = 0.0; out[1] = 0.0; out[2] = 0.0;
    if (!s->touching[i]) return;
    double n[3], t1[3], t2[3], e[3];
    double d = depth(s, p, n, err);
    if (d <= 0.0) return;
    double vn = pv[0] * n[0] + pv[1] * n[1] + pv[2] * n[2];
    double spring = s->normal_pad ? pad_force(s, d, err) : s->normal_k * d;
    double fn = leg_max(0.0, spring - s->normal_b * vn);
    tangents(n, t1, t2);
    const double *a = s->anchor + 3 * i;
    e[0] = p[0] - a[0]; e[1] = p[1] - a[1]; e[2] = p[2] - a[2];
    double k = s->tangent_k, b = s->tangent_b;
    double f1 = -k * (e[0] * t1[0] + e[1] * t1[1] + e[2] * t1[2])
                - b * (pv[0] * t1[0] + pv[1] * t1[1] + pv[2] * t1[2]);
    double f2 = 0.0;
    if (!LEG_PLANAR) {
        f2 = -k * (e[0] * t2[0] + e[1] * t2[1] + e[2] * t2[2])
             - b * (pv[0] * t2[0] + pv[1] * t2[1] + pv[2] * t2[2]);
    }
    if (s->has_friction) {
        double mu = s->friction;
        double ft = leg_hypot(f1, f2);
        if (ft > mu * fn && ft > 0.0) {
            double scale = leg_div(mu * fn, ft);
            double g1 = f1 * scale, g2 = f2 * scale;
            f1 = g1; f2 = g2;
        }
    }
    out[0] = fn * n[0] + f1 * t1[0] + f2 * t2[0];
    out[1] = fn * n[1] + f1 * t1[1] + f2 * t2[1];
    out[2] = fn * n[2] + f1 * t1[2] + f2 * t2[2];
}

/* GroundContact.yaw: a body's turn about the ground's normal (rot row by row) */
static double ground_yaw(const leg_sim *s, const double *rot) {
    if (!s->has_slope) return atan2(rot[3], rot[0]);
    double a = s->slope_angle;
    return atan2(rot[3], cos(a) * rot[0] + sin(a) * rot[6]);
}

/* GroundContact.about_normal: a body's angular Jacobian row about the ground's normal */
static const double *about_normal(const leg_sim *s, const double *jw, double *row) {
    if (!s->has_slope) return jw + 2 * NV;
    double a = s->slope_angle;
    double nx = -sin(a), nz = cos(a);
    for (int k = 0; k < NV; k++) row[k] = nx * jw[k] + nz * jw[2 * NV + k];
    return row;
}

static double ground_torsion(const leg_sim *s, int i, double yaw, double rate, int *err) {
    if (!s->touching[i]) return 0.0;
    double e = leg_remainder_e(yaw - s->yaw_anchor[i], PY_TAU, err);
    return -s->torsion_k * e - s->torsion_b * rate;
}

/* Outside the friction cone the foot slides; where the spring alone pulls harder than the cone,
 * the anchor follows the foot, straight towards it, until the spring holds exactly the cone's
 * force (GroundContact._slip). */
static void slip(leg_sim *s, int i, const double *p, const double *pv, double d, const double *n,
                 int *err) {
    double f[3], t1[3], t2[3], e[3];
    ground_force(s, i, p, pv, f, err);
    double fn = f[0] * n[0] + f[1] * n[1] + f[2] * n[2];
    tangents(n, t1, t2);
    double *a = s->anchor + 3 * i;
    e[0] = p[0] - a[0]; e[1] = p[1] - a[1]; e[2] = p[2] - a[2];
    double k = s->tangent_k, b = s->tangent_b;
    double s1 = -k * dot3(e, t1);
    double s2 = LEG_PLANAR ? 0.0 : -k * dot3(e, t2);
    double f1 = s1 - b * dot3(pv, t1);
    double f2 = LEG_PLANAR ? 0.0 : s2 - b * dot3(pv, t2);
    double limit = s->friction * fn;
    s->slipping[i] = leg_hypot(f1, f2) > limit;
    double st = leg_hypot(s1, s2);
    if (!(st > limit) || k <= 0.0) return;
    double scale = leg_div(limit, st);
    double off1 = leg_div(s1 * scale, k);
    double off2 = leg_div(s2 * scale, k);
    double base[3] = {p[0] + d * n[0], p[1] + d * n[1], p[2] + d * n[2]};
    a[0] = base[0] + off1 * t1[0] + off2 * t2[0];
    a[1] = base[1] + off1 * t1[1] + off2 * t2[1];
    a[2] = base[2] + off1 * t1[2] + off2 * t2[2];
}

/* Touchdowns, liftoffs and slip at a step boundary (GroundContact.update). */
static int ground_update(leg_sim *s, double t, const double *pos, const double *vel,
                         const double *yaws, int *err) {
    for (int i = 0; i < NC; i++) {
        const double *p = pos + 3 * i;
        double n[3];
        double d = depth(s, p, n, err);
        if (d > 0.0 && !s->touching[i]) {
            s->touching[i] = 1;
            s->anchor[3 * i] = p[0] + d * n[0];
            s->anchor[3 * i + 1] = p[1] + d * n[1];
            s->anchor[3 * i + 2] = p[2] + d * n[2];
            s->yaw_anchor[i] = yaws != 0 ? yaws[i] : 0.0;
            s->event_t[s->n_events] = t; s->event_kind[s->n_events] = 1;
            s->event_contact[s->n_events++] = i;
        } else if (d <= 0.0 && s->touching[i]) {
            s->touching[i] = 0;
            s->slipping[i] = 0;
            s->event_t[s->n_events] = t; s->event_kind[s->n_events] = 0;
            s->event_contact[s->n_events++] = i;
        } else if (s->touching[i] && s->has_friction) {
            slip(s, i, p, vel + 3 * i, d, n, err);
        }
    }
    return 0;
}

/* Contact positions, velocities and (3D with torsion) body yaws (_contact_kinematics); the
 * velocities and yaws are zeros while every foot is in the air and above the ground
 * (GroundContact.near: no foot touches or is at or under it). Near it, only the feet that
 * touch or are at or under the ground get theirs (the others' are zeros here, not Python's
 * values): the forces, slip and touchdowns read no other foot's (the feet touching after this
 * state's update are among them). The _some functions (dynamics_some.c) compute those outputs as
 * the whole functions do, and fail where they fail. */
static void contact_kinematics(const leg_sim *s, const double *q, const double *v, double *pos,
                               double *vel, double *yaws, int *err) {
    contact_positions(q, pos, err);
    for (int k = 0; k < 3 * NC; k++) vel[k] = 0.0;
    for (int i = 0; i < NC; i++) yaws[i] = 0.0;
    unsigned char feet[NC3];
    double n[3];
    int near = 0;
    for (int i = 0; i < NC; i++) {
        feet[i] = s->touching[i] || depth(s, pos + 3 * i, n, err) > 0.0;
        near |= feet[i];
    }
    if (!near) return;
    if (s->torsion) {
        double poses[NBP];
        unsigned char rotations[2 * LEG_NB];
        for (int b = 0; b < 2 * LEG_NB; b++) rotations[b] = 0;
        for (int i = 0; i < NC; i++) rotations[2 * s->contact_body[i] + 1] |= feet[i];
        body_poses_some(q, rotations, poses, err);
        for (int i = 0; i < NC; i++) {
            const double *rot = poses + 12 * s->contact_body[i] + 3;
            if (feet[i]) yaws[i] = ground_yaw(s, rot);
        }
    }
    contact_velocities_some(q, v, feet, vel, err);
}

/* ------------------------------------------------------------ forces (Simulation.generalized_forces) */
static void generalized_forces(leg_sim *s, const double *q, const double *v, int record,
                               double *tau, int *err) {
    for (int k = 0; k < NV; k++) tau[k] = 0.0;
    for (int64_t a = 0; a < s->n_act; a++) { /* ActuatorBank.apply */
        double f;
        if (s->act_is_force[a]) {
            f = s->act_force[a];
        } else {
            f = -s->act_gain[a] * (q[s->act_qi[a]] - s->act_target[a])
                - s->act_damping[a] * v[s->act_vi[a]];
        }
        if (s->act_has_limit[a]) f = leg_max(-s->act_limit[a], leg_min(s->act_limit[a], f));
        s->act_last[a] = f;
        tau[s->act_vi[a]] += f;
    }
    for (int64_t k = 0; k < s->n_stops; k++) { /* one-sided spring-dampers at the joint limits */
        double x = q[s->stop_qi[k]];
        if (x < s->stop_low[k]) {
            double push = s->stop_k[k] * (s->stop_low[k] - x) - s->stop_b[k] * v[s->stop_vi[k]];
            if (push > 0) tau[s->stop_vi[k]] += push;
        } else if (x > s->stop_high[k]) {
            double push = s->stop_k[k] * (s->stop_high[k] - x) - s->stop_b[k] * v[s->stop_vi[k]];
            if (push < 0) tau[s->stop_vi[k]] += push;
        }
    }
    int any = 0;
    for (int i = 0; i < NC; i++) any |= s->has_ground && s->touching[i];
    if (any) {
        double pos[NC3], vel[NC3], yaws[NC3], jac[NCJ], f[3];
        if (q == s->q && v == s->v && s->kin_valid) { /* found at the end of the last step */
            for (int k = 0; k < 3 * NC; k++) { pos[k] = s->kin[k]; vel[k] = s->kin[3 * NC + k]; }
            for (int k = 0; k < NC; k++) yaws[k] = s->kin[6 * NC + k];
        } else {
            contact_kinematics(s, q, v, pos, vel, yaws, err);
        }
        unsigned char touching[NC3];
        for (int i = 0; i < NC; i++) touching[i] = (unsigned char)s->touching[i];
        contact_jacobians_some(q, touching, jac, err); /* the rows of the feet that push */
        for (int i = 0; i < NC; i++) {
            if (!s->touching[i]) {
                if (record) {
                    s->contact_force[3 * i] = 0.0;
                    s->contact_force[3 * i + 1] = 0.0;
                    s->contact_force[3 * i + 2] = 0.0;
                }
                continue;
            }
            ground_force(s, i, pos + 3 * i, vel + 3 * i, f, err);
            if (record) {
                s->contact_force[3 * i] = f[0];
                s->contact_force[3 * i + 1] = f[1];
                s->contact_force[3 * i + 2] = f[2];
            }
            const double *jx = jac + 3 * NV * i, *jy = jx + NV, *jz = jy + NV;
            for (int k = 0; k < NV; k++) tau[k] += jx[k] * f[0] + jy[k] * f[1] + jz[k] * f[2];
        }
        if (s->torsion) { /* Simulation._add_torsion */
            double jw[NCJ];
            contact_angular_jacobians_some(q, touching, jw, err);
            for (int i = 0; i < NC; i++) {
                if (!s->touching[i]) continue;
                double row[NV];
                const double *jn = about_normal(s, jw + 3 * NV * i, row);
                double rate = 0.0;
                for (int k = 0; k < NV; k++) rate += jn[k] * v[k];
                double torque = ground_torsion(s, i, yaws[i], rate, err);
                for (int k = 0; k < NV; k++) tau[k] += jn[k] * torque;
            }
        }
    } else if (record) {
        for (int i = 0; i < 3 * NC; i++) s->contact_force[i] = 0.0;
    }
}

static void accel(leg_sim *s, const double *q, const double *v, int record, double *a, int *err) {
    double tau[NV];
    generalized_forces(s, q, v, record, tau, err);
    forward_dynamics(q, v, tau, a, err);
}

/* ------------------------------------------------------------ integration (Simulation.step) */
static void qdot(const double *q, const double *v, double *out) {
    if (!LEG_FREE3D) {
        for (int k = 0; k < NV; k++) out[k] = v[k];
        return;
    }
#if LEG_FREE3D
    double qw = q[3], qx = q[4], qy = q[5], qz = q[6];
    double wx = v[3], wy = v[4], wz = v[5];
    out[0] = v[0]; out[1] = v[1]; out[2] = v[2];
    out[3] = 0.5 * (-qx * wx - qy * wy - qz * wz);
    out[4] = 0.5 * (qw * wx + qy * wz - qz * wy);
    out[5] = 0.5 * (qw * wy - qx * wz + qz * wx);
    out[6] = 0.5 * (qw * wz + qx * wy - qy * wx);
    for (int k = 6; k < NV; k++) out[k + 1] = v[k];
#endif
}

static void advance_positions(const double *q, const double *v, double dt, double *out, int *err) {
    if (!LEG_FREE3D) {
        for (int k = 0; k < NQ; k++) out[k] = q[k] + dt * v[k];
        return;
    }
#if LEG_FREE3D
    out[0] = q[0] + dt * v[0]; out[1] = q[1] + dt * v[1]; out[2] = q[2] + dt * v[2];
    double wx = v[3], wy = v[4], wz = v[5];
    double angle = leg_sqrt(wx * wx + wy * wy + wz * wz) * dt;
    double dw, dx, dy, dz;
    if (angle > 1e-12) {
        double sn = leg_div(leg_sin(leg_div(angle, 2.0)), leg_div(angle, dt));
        dw = leg_cos(leg_div(angle, 2.0)); dx = wx * sn; dy = wy * sn; dz = wz * sn;
    } else {
        dw = 1.0; dx = leg_div(wx * dt, 2.0); dy = leg_div(wy * dt, 2.0); dz = leg_div(wz * dt, 2.0);
    }
    double qw = q[3], qx = q[4], qy = q[5], qz = q[6];
    double quat[4] = {
        qw * dw - qx * dx - qy * dy - qz * dz,
        qw * dx + qx * dw + qy * dz - qz * dy,
        qw * dy - qx * dz + qy * dw + qz * dx,
        qw * dz + qx * dy - qy * dx + qz * dw,
    };
    double sum = 0.0;
    for (int k = 0; k < 4; k++) sum += quat[k] * quat[k];
    double norm = leg_sqrt(sum);
    for (int k = 0; k < 4; k++) out[3 + k] = leg_div(quat[k], norm);
    for (int k = 7; k < NQ; k++) out[k] = q[k] + dt * v[k - 1];
#endif
}

static void normalise(double *q, int *err) {
#if LEG_FREE3D
    double norm = leg_sqrt(q[3] * q[3] + q[4] * q[4] + q[5] * q[5] + q[6] * q[6]);
    for (int i = 3; i < 7; i++) q[i] = leg_div(q[i], norm);
#else
    (void)q; (void)err;
#endif
}

/* The contact kinematics at the state now: the next forces at this state reuse them, as
 * Simulation._contact_kinematics does (the same values, computed once). */
static void remember_kinematics(leg_sim *s, const double *pos, const double *vel,
                                const double *yaws) {
    for (int k = 0; k < 3 * NC; k++) { s->kin[k] = pos[k]; s->kin[3 * NC + k] = vel[k]; }
    for (int k = 0; k < NC; k++) s->kin[6 * NC + k] = s->torsion ? yaws[k] : 0.0;
    s->kin_valid = 1;
}

/* Each actuator's power: the force the last forces found times its rate in v (W). */
static void power(const leg_sim *s, const double *v, double *out) {
    for (int64_t a = 0; a < s->n_act; a++) out[a] = s->act_last[a] * v[s->act_vi[a]];
}

/* One step's work at power p (ActuatorBank.add_work): act_work holds the n_act positive
 * sums, then the n_act negative ones. */
static void add_work(leg_sim *s, const double *p, double dt) {
    for (int64_t a = 0; a < s->n_act; a++) {
        if (p[a] > 0.0) s->act_work[a] += p[a] * dt;
        else s->act_work[s->n_act + a] += p[a] * dt;
    }
}

/* One step; 0, or LEG_RAISED with the state as Python leaves it when it raises there. */
static int step(leg_sim *s) {
    int e = 0;
    int *err = &e;
    double dt = s->dt;
    double qn[NQ], vn[NV];
    const double *q = s->q, *v = s->v;
    int64_t na = s->n_act;
    double pw[4 * na + 1]; /* the step's power (Euler), or each RK4 stage's */
    if (!s->rk4) {
        double a[NV];
        accel(s, q, v, 1, a, err);
        if (e) goto raised;
        for (int k = 0; k < NV; k++) vn[k] = v[k] + dt * a[k];
        advance_positions(q, vn, dt, qn, err);
        if (e) goto raised;
        double mean[NV]; /* the rates at the step's two ends, averaged */
        for (int k = 0; k < NV; k++) mean[k] = 0.5 * (v[k] + vn[k]);
        power(s, mean, pw);
    } else {
        double k1q[NQ], k1v[NV], k2q[NQ], k2v[NV], k3q[NQ], k3v[NV], k4q[NQ], k4v[NV];
        double q2[NQ], v2[NV], q3[NQ], v3[NV], q4[NQ], v4[NV];
        qdot(q, v, k1q);
        accel(s, q, v, 1, k1v, err);
        if (e) goto raised;
        power(s, v, pw);
        for (int k = 0; k < NQ; k++) q2[k] = q[k] + 0.5 * dt * k1q[k];
        for (int k = 0; k < NV; k++) v2[k] = v[k] + 0.5 * dt * k1v[k];
        qdot(q2, v2, k2q);
        accel(s, q2, v2, 0, k2v, err);
        if (e) goto raised;
        power(s, v2, pw + na);
        for (int k = 0; k < NQ; k++) q3[k] = q[k] + 0.5 * dt * k2q[k];
        for (int k = 0; k < NV; k++) v3[k] = v[k] + 0.5 * dt * k2v[k];
        qdot(q3, v3, k3q);
        accel(s, q3, v3, 0, k3v, err);
        if (e) goto raised;
        power(s, v3, pw + 2 * na);
        for (int k = 0; k < NQ; k++) q4[k] = q[k] + dt * k3q[k];
        for (int k = 0; k < NV; k++) v4[k] = v[k] + dt * k3v[k];
        qdot(q4, v4, k4q);
        accel(s, q4, v4, 0, k4v, err);
        if (e) goto raised;
        power(s, v4, pw + 3 * na);
        for (int64_t k = 0; k < na; k++)
            pw[k] = (pw[k] + 2.0 * pw[na + k] + 2.0 * pw[2 * na + k] + pw[3 * na + k]) / 6.0;
        double sixth = leg_div(dt, 6.0);
        for (int k = 0; k < NQ; k++)
            qn[k] = q[k] + sixth * (k1q[k] + 2.0 * k2q[k] + 2.0 * k3q[k] + k4q[k]);
        for (int k = 0; k < NV; k++)
            vn[k] = v[k] + sixth * (k1v[k] + 2.0 * k2v[k] + 2.0 * k3v[k] + k4v[k]);
        normalise(qn, err);
        if (e) goto raised;
    }
    for (int k = 0; k < NQ; k++) s->q[k] = qn[k];
    for (int k = 0; k < NV; k++) s->v[k] = vn[k];
    add_work(s, pw, dt);
    s->kin_valid = 0;
    s->steps_taken += 1;
    for (int64_t k = 0; k < s->n_stops; k++) {
        double x = s->q[s->stop_qi[k]];
        if (!(s->stop_low[k] <= x && x <= s->stop_high[k])) s->stop_time[k] += dt;
    }
    s->t = (double)s->steps_taken * dt;
    if (s->has_ground) {
        double pos[NC3], vel[NC3], yaws[NC3];
        contact_kinematics(s, s->q, s->v, pos, vel, yaws, err);
        if (e) goto raised;
        remember_kinematics(s, pos, vel, yaws);
        ground_update(s, s->t, pos, vel, s->torsion ? yaws : 0, err);
        if (e) goto raised;
    }
    return 0;
raised:
    s->err = e;
    return LEG_RAISED;
}

/* ------------------------------------------------------------ recording (recorder.py) */
/* actuators.stored: what a spring holds, its force clipped to its max (has_limit) */
static double spring_stored(double gain, double stretch, int64_t has_limit, double limit) {
    if (!has_limit || !(fabs(gain * stretch) > limit)) return 0.5 * gain * stretch * stretch;
    double beyond = limit * (fabs(stretch) - 0.5 * limit / fabs(gain));
    return gain > 0.0 ? beyond : -beyond;
}

static double springs_energy(const leg_sim *s, const double *q, const int64_t *mask) {
    double total = 0.0;
    for (int64_t a = 0; a < s->n_act; a++) {
        if (!s->act_is_force[a] && (mask == 0 || mask[a])) {
            double d = q[s->act_qi[a]] - s->act_target[a];
            total += spring_stored(s->act_gain[a], d, s->act_has_limit[a], s->act_limit[a]);
        }
    }
    return total;
}

static double pad_energy(const leg_sim *s, double dep, int *err) {
    double t = s->pad_thickness, k = s->normal_k;
    double d = leg_min(dep, 0.9 * t);
    double energy = k * (-t * leg_log(leg_div(t - d, t)) - d);
    if (dep > d) {
        double f0 = k * (leg_div(t, t - d) - 1.0);
        double slope = leg_div(k * t, leg_pow(t - d, 2.0));
        double x = dep - d;
        energy += f0 * x + 0.5 * slope * x * x;
    }
    return energy;
}

/* The elastic energy of Simulation.energy: actuator springs, stops, ground springs. */
static double elastic_energy(const leg_sim *s, int *err) {
    const double *q = s->q;
    double elastic = springs_energy(s, q, 0);
    for (int64_t k = 0; k < s->n_stops; k++) {
        double x = q[s->stop_qi[k]];
        double past = x < s->stop_low[k] ? s->stop_low[k] - x
                      : x > s->stop_high[k] ? x - s->stop_high[k] : 0.0;
        elastic += 0.5 * s->stop_k[k] * past * past;
    }
    if (s->has_ground) {
        double pos[NC3], n[3], t1[3], t2[3], e[3];
        contact_positions(q, pos, err);
        double total = 0.0;
        for (int i = 0; i < NC; i++) {
            if (!s->touching[i]) continue;
            const double *p = pos + 3 * i;
            double d = depth(s, p, n, err);
            if (d <= 0.0) continue;
            if (s->normal_pad) total += pad_energy(s, d, err);
            else total += 0.5 * s->normal_k * d * d;
            const double *a = s->anchor + 3 * i;
            e[0] = p[0] - a[0]; e[1] = p[1] - a[1]; e[2] = p[2] - a[2];
            tangents(n, t1, t2);
            double e1 = dot3(e, t1);
            double e2 = LEG_PLANAR ? 0.0 : dot3(e, t2);
            total += 0.5 * s->tangent_k * (e1 * e1 + e2 * e2);
        }
        elastic += total;
    }
    return elastic;
}

static int all_finite(const double *x, int n) {
    for (int k = 0; k < n; k++)
        if (!isfinite(x[k])) return 0;
    return 1;
}

/* One row of the recording (record_row); 0, LEG_NONFINITE or LEG_RAISED. */
static int record_row(leg_sim *s, int64_t row) {
    int e = 0;
    int *err = &e;
    const double *q = s->q, *v = s->v;
    if (!all_finite(q, NQ) || !all_finite(v, NV)) return LEG_NONFINITE;
    s->rec_t[row] = s->t;
    for (int k = 0; k < NQ; k++) s->rec_q[row * NQ + k] = q[k];
    for (int k = 0; k < NV; k++) s->rec_v[row * NV + k] = v[k];
    if (s->has_ground) {
        for (int i = 0; i < NC; i++) s->rec_contact[row * NC + i] = (int8_t)s->touching[i];
        for (int i = 0; i < 3 * NC; i++) s->rec_force[row * 3 * NC + i] = s->contact_force[i];
    }
    center_of_mass(q, s->rec_com + 3 * row, err);
    center_of_mass_velocity(q, v, s->rec_com_vel + 3 * row, err);
    double poses[NBP];
    unsigned char read[2 * LEG_NB]; /* the root's pose and the hips' positions (record_row's) */
    for (int b = 0; b < 2 * LEG_NB; b++) read[b] = b < 2;
    for (int64_t i = 0; i < s->n_legs; i++) {
        read[2 * s->leg_hip[i]] = 1;
        if (s->leg_hip_moved[i]) read[2 * s->leg_hip[i] + 1] = 1; /* its rotation, for Hip.point */
    }
    body_poses_some(q, read, poses, err);
    const double *rot = poses + 3;
    for (int k = 0; k < 3; k++) s->rec_root_pos[3 * row + k] = poses[k];
    if (LEG_PLANAR && rot[8] < 0.0) { /* a planar pitch past 90 deg, over the whole turn */
        s->rec_root_rpy[3 * row] = s->rec_root_rpy[3 * row + 2] = 0.0;
        s->rec_root_rpy[3 * row + 1] = leg_whole_turn_pitch(rot, err);
    } else {
        s->rec_root_rpy[3 * row] = atan2(rot[7], rot[8]);
        s->rec_root_rpy[3 * row + 1] = leg_asin(leg_max(-1.0, leg_min(1.0, -rot[6])));
        s->rec_root_rpy[3 * row + 2] = atan2(rot[3], rot[0]);
    }
    if (s->n_legs > 0) {
        double feet[NC3];
        contact_positions(q, feet, err);
        for (int64_t i = 0; i < s->n_legs; i++) {
            double h[3], a[3];
            leg_hip_point(poses + 12 * s->leg_hip[i],
                          s->leg_hip_moved[i] ? s->leg_hip_at + 3 * i : 0, h, a);
            s->rec_leg_length[row * s->n_legs + i] = leg_dist3(h, feet + 3 * s->leg_foot[i]);
            s->rec_leg_spring_energy[row * s->n_legs + i] =
                springs_energy(s, q, s->leg_spring + i * s->n_act);
        }
    }
    double elastic = elastic_energy(s, err);
    double kinetic, potential;
    kinetic_energy(q, v, &kinetic, err);
    potential_energy(q, &potential, err);
    s->rec_kinetic[row] = kinetic;
    s->rec_potential[row] = potential;
    s->rec_elastic[row] = elastic;
    if (s->has_controller) {
        s->rec_state[row] = (int16_t)s->state_index;
        s->rec_speed_command[row] = s->speed_command;
    }
    for (int64_t a = 0; a < s->n_act; a++) {
        s->rec_work_positive[row * s->n_act + a] = s->act_work[a];
        s->rec_work_negative[row * s->n_act + a] = s->act_work[s->n_act + a];
    }
    if (e) {
        s->err = e;
        return LEG_RAISED;
    }
    return 0;
}

/* The fall and divergence rules of Simulation._check: 1 when the run must stop. */
static int check_fails(leg_sim *s) {
    int e = 0;
    int *err = &e;
    if (!all_finite(s->v, NV) || !all_finite(s->q, NQ)) return 1;
    /* sizes.too_fast: the limit of a creature of the scaled size, in its numbers */
    double size = s->size_scale * s->start_height;
    double most = 1e3; /* sizes.divergence_speed */
    if (size > 0 && size < 0.1) most = 1e3 * sqrt(0.1 / size);
    for (int k = 0; k < NV; k++)
        if (fabs(s->v[k]) > most / s->v_factor[k]) return 1;
    double poses[NBP];
    const unsigned char root[2 * LEG_NB] = {1, 1}; /* its position and rotation: all _check reads */
    body_poses_some(s->q, root, poses, err);
    if (e) return 1; /* Python raises here: it says so */
    const double *rot = poses + 3;
    double tilt = leg_acos(leg_max(-1.0, leg_min(1.0, rot[8])));
    double limit;
    int has_limit = 1;
    if (s->has_fall_height) limit = s->fall_height;
    else if (s->start_height > 0) limit = 0.3 * s->start_height;
    else has_limit = 0;
    double under = s->has_ground ? height(s, poses[0], poses[1], err) : 0.0;
    double above = poses[2] - under;
    if (e) return 1;
    if (has_limit && above < limit) return 1;
    if (tilt > s->fall_tilt) return 1;
    return 0;
}

/* ------------------------------------------------------------ the run loop (Simulation.run) */

/* The ground's first look at the contacts, at t = 0 (before the loop). */
int64_t leg_begin(leg_sim *s) {
    int e = 0;
    int *err = &e;
    if (s->has_ground) {
        double pos[NC3], vel[NC3], yaws[NC3];
        contact_kinematics(s, s->q, s->v, pos, vel, yaws, err);
        if (!e) remember_kinematics(s, pos, vel, yaws);
        if (!e) ground_update(s, 0.0, pos, vel, s->torsion ? yaws : 0, err);
    }
    s->err = e;
    return e ? LEG_RAISED : 0;
}

/* Whether a switching run's Python (legdsl.sim.switching.SwitchingMachine) must take this
 * tick: a command is due, or a switch is and its controller may take over now (at a foot's
 * liftoff, the first this tick's Sensors.observe sees, until ctl_switch_until; then at
 * once). The other ticks the current controller's machine takes in C. */
static int switching_tick(const leg_sim *s) {
    double t = s->t;
    if (s->ctl_command_at <= t + 1e-12) return 1;
    if (s->ctl_switch_at > t + 1e-12) return 0;
    if (t >= s->ctl_switch_until - 1e-12) return 1;
    for (int i = 0; i < NC; i++)
        if (s->clocks[5 * i] != 0.0 && !(s->has_ground && s->touching[i])) return 1;
    return 0;
}

/* Run from (s->steps, s->phase) until the run ends or Python is needed; see the enum above.
 * Phases of one pass: 0 the controller, 1 recording, 2 the check, 3 the step. */
int64_t leg_run(leg_sim *s) {
    int64_t budget = s->step_budget;
    for (;;) {
        int64_t steps = s->steps;
        int tick = steps % s->control_every == 0;
        if (s->phase == 0) {
            s->phase = 1;
            if (tick && s->has_controller) {
                /* Python takes this tick: no C twin, a switching run's business, or C gave
                 * up on it */
                if (!s->c_control || switching_tick(s)) return LEG_CONTROL;
                if (leg_control_tick(s)) return LEG_CONTROL;
            }
        }
        if (s->phase == 1) {
            if (steps % s->record_every == 0) {
                if (s->recorded == s->rows) return LEG_FULL;
                int e = 0;
                double tau[NV];
                generalized_forces(s, s->q, s->v, 1, tau, &e);
                if (e) {
                    s->err = e;
                    return LEG_RAISED;
                }
                int code = record_row(s, s->recorded);
                if (code) return code;
                s->recorded += 1;
            }
            s->phase = 2;
        }
        if (s->phase == 2) {
            int check = steps % s->check_every == 0 || steps == s->n_steps;
            if (check && check_fails(s)) return LEG_CHECK;
            s->phase = 3;
        }
        if (steps == s->n_steps) return LEG_DONE;
        if (s->n_events + NC > s->event_cap) return LEG_YIELD; /* Python drains the events */
        int code = step(s);
        if (code) return code;
        s->steps = steps + 1;
        s->phase = 0;
        if (--budget <= 0) return LEG_YIELD;
    }
}

/* Wrappers of the generated functions for Python (tests, sensors): err returned. */
int64_t leg_call_forward_dynamics(const double *q, const double *v, const double *tau, double *out) {
    int e = 0;
    forward_dynamics(q, v, tau, out, &e);
    return e;
}

/* forward_dynamics n times at one state, for the benchmark (benchmarks/bench_c_backend.py):
 * it lives in another translation unit, so the compiler cannot hoist the call out. */
int64_t leg_bench_forward_dynamics(const double *q, const double *v, const double *tau, int64_t n,
                                   double *out) {
    int e = 0;
    for (int64_t k = 0; k < n; k++) forward_dynamics(q, v, tau, out, &e);
    return e;
}
