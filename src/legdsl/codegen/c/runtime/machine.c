/* machine.c: the controller's state machine and sensors in C (the C backend's runtime).
 *
 * A transliteration of legdsl/sim/machine.py (StateMachine.__call__: the input schedule, the
 * event of the next state, entry records, the actions' settings) and legdsl/sim/sensors.py
 * (the stance and flight clocks, the sensor values), keeping each expression's operations in
 * the Python order. Where the Python would raise or fault (a math error, an output that is
 * not finite, a state that is no longer finite), this tick is undone and handed to the Python
 * state machine, which then fails exactly as on the Python backend (or, if it does not fail,
 * continues): leg_control_tick returns LEG_CONTROL. Identity: tests/sim/test_c_backend.py.
 */
#include <math.h>
#include <string.h>

#include "legdsl_math.h"
#include "legdsl_sim.h"
#include "legdsl_sizes.h"
#include "legdsl_model.h"
#include "legdsl_control.h"

#define NB LEG_NB
#define NC LEG_NC
#define NCS (3 * LEG_NC + 1)

/* ------------------------------------------------------------ the per-tick kinematics cache */
/* One per thread: runs of a batch go on in parallel threads (legdsl.pipeline.backend.run_batch).
 * Each sensor function finds it once (kc) and hands it on: in a shared library every reach
 * for a thread's variable is a call (__tls_get_addr). */
typedef struct {
    int feet, com, heading, angles_of; /* angles_of: the body of angles, or -1 */
    double pose[12 * NB], velocity[6 * NB], foot[NCS], foot_v[NCS], c[3], cv[3], hc, hs;
    double angles[6]; /* euler_rates of one body: roll, pitch, yaw and their rates */
    /* parts of body_poses and body_velocities (a body's position or linear velocity, its
     * rotation or angular velocity): found this tick, and read by the sensors in any tick */
    unsigned char pose_found[2 * NB], vel_found[2 * NB], pose_read[2 * NB], vel_read[2 * NB];
} sense_cache;
static __thread sense_cache K;
#if defined(__GNUC__) && !defined(__clang__)
#define LEG_OPAQUE __attribute__((noipa)) /* else gcc passes &K on as a constant, found again */
#else
#define LEG_OPAQUE __attribute__((noinline))
#endif
static LEG_OPAQUE sense_cache *this_thread(void) { return &K; }

static __thread int path_fresh[64];
void leg_sense_begin(void) {
    sense_cache *const kc = this_thread();
    kc->feet = kc->com = kc->heading = 0;
    kc->angles_of = -1;
    memset(kc->pose_found, 0, sizeof kc->pose_found);
    memset(kc->vel_found, 0, sizeof kc->vel_found);
    for (int k = 0; k < 64; k++) path_fresh[k] = 0;
}

/* Body b's part (and, with both, its second part) of a body function's result. Python
 * computes the whole function once a tick; the sensors read a few bodies, the same ones at
 * every tick, so the first read of a tick computes every part read so far with the _some
 * function (dynamics_some.c: the same doubles, and it fails where the whole function fails). */
static int to_find(unsigned char *want, const unsigned char *found, unsigned char *read, int b,
                   int both) {
    read[2 * b] = 1;
    if (both) read[2 * b + 1] = 1;
    int any = 0;
    for (int p = 0; p < 2 * NB; p++) any |= want[p] = read[p] && !found[p];
    return any;
}
static const double *pose(sense_cache *kc, leg_sim *s, int b, int both, int *err) {
    if (!kc->pose_found[2 * b] || (both && !kc->pose_found[2 * b + 1])) {
        unsigned char want[2 * NB];
        if (to_find(want, kc->pose_found, kc->pose_read, b, both))
            body_poses_some(s->q, want, kc->pose, err);
        for (int p = 0; p < 2 * NB; p++) kc->pose_found[p] |= want[p];
    }
    return kc->pose + 12 * b;
}
static const double *velocity(sense_cache *kc, leg_sim *s, int b, int both, int *err) {
    if (!kc->vel_found[2 * b] || (both && !kc->vel_found[2 * b + 1])) {
        unsigned char want[2 * NB];
        if (to_find(want, kc->vel_found, kc->vel_read, b, both))
            body_velocities_some(s->q, s->v, want, kc->velocity, err);
        for (int p = 0; p < 2 * NB; p++) kc->vel_found[p] |= want[p];
    }
    return kc->velocity + 6 * b;
}

static void feet(sense_cache *kc, leg_sim *s, int *err) {
    if (!kc->feet) {
        contact_positions(s->q, kc->foot, err);
        contact_velocities(s->q, s->v, kc->foot_v, err);
        kc->feet = 1;
    }
}
static void com(sense_cache *kc, leg_sim *s, int *err) {
    if (!kc->com) {
        center_of_mass(s->q, kc->c, err);
        center_of_mass_velocity(s->q, s->v, kc->cv, err);
        kc->com = 1;
    }
}
static void heading(sense_cache *kc, leg_sim *s, int *err) {
    if (!kc->heading) {
        const double *rot = pose(kc, s, 0, 1, err) + 3;
        double yaw = LEG_PLANAR ? 0.0 : atan2(rot[3], rot[0]);
        kc->hc = leg_cos(yaw);
        kc->hs = leg_sin(yaw);
        kc->heading = 1;
    }
}
static double to_heading(sense_cache *kc, leg_sim *s, const double *vec, int axis, int *err) {
    heading(kc, s, err);
    double c = kc->hc, sn = kc->hs;
    if (axis == 0) return c * vec[0] + sn * vec[1];
    if (axis == 1) return -sn * vec[0] + c * vec[1];
    return vec[2];
}

/* ------------------------------------------------------------ sensor values (Sensors._value) */
double leg_sense_com(leg_sim *s, int axis, int velocity, int *err) {
    sense_cache *const kc = this_thread();
    com(kc, s, err);
    return velocity ? kc->cv[axis] : kc->c[axis];
}

double leg_sense_contact(leg_sim *s, int i, int member, int *err) {
    if (member == 0) return s->has_ground && s->touching[i] ? 1.0 : 0.0;
    sense_cache *const kc = this_thread();
    feet(kc, s, err);
    return member >= 4 ? kc->foot_v[3 * i + member - 4] : kc->foot[3 * i + member - 1];
}

double leg_sense_act(const leg_sim *s, int a, int member) {
    if (member == 0) return s->act_gain[a];
    if (member == 1) return s->act_damping[a];
    if (member == 2) return s->act_target[a];
    return s->act_last[a];
}

double leg_sense_body(leg_sim *s, int b, int member, int *err) {
    sense_cache *const kc = this_thread();
    const double *pose_b = pose(kc, s, b, member >= 6, err);
    if (member < 3) return pose_b[member];
    const double *vel = velocity(kc, s, b, member >= 6, err);
    if (member < 6) return vel[member - 3];
    if (kc->angles_of != b && LEG_PLANAR && pose_b[3 + 8] < 0.0) { /* a planar pitch past 90 deg */
        kc->angles[0] = kc->angles[2] = kc->angles[3] = kc->angles[5] = 0.0;
        kc->angles[1] = leg_whole_turn_pitch(pose_b + 3, err);
        kc->angles[4] = vel[3 + 1];
        kc->angles_of = b;
    }
    if (kc->angles_of != b) { /* euler_rates, once a tick for all six of a body's readings */
        const double *rot = pose_b + 3, *omega = vel + 3;
        double roll = atan2(rot[7], rot[8]);
        double pitch = leg_asin(leg_max(-1.0, leg_min(1.0, -rot[6])));
        double yaw = atan2(rot[3], rot[0]);
        double bx = rot[0] * omega[0] + rot[3] * omega[1] + rot[6] * omega[2];
        double by = rot[1] * omega[0] + rot[4] * omega[1] + rot[7] * omega[2];
        double bz = rot[2] * omega[0] + rot[5] * omega[1] + rot[8] * omega[2];
        double sr = leg_sin(roll), cr = leg_cos(roll);
        double cp = leg_cos(pitch);
        cp = fabs(cp) > 1e-9 ? cp : copysign(1e-9, cp);
        kc->angles[0] = roll;
        kc->angles[1] = pitch;
        kc->angles[2] = yaw;
        kc->angles[3] = bx + (by * sr + bz * cr) * leg_tan(pitch);
        kc->angles[4] = by * cr - bz * sr;
        kc->angles[5] = leg_div(by * sr + bz * cr, cp);
        kc->angles_of = b;
    }
    return kc->angles[member - 6];
}

/* A leg's hip point (ir.model.Hip.point), and its velocity (Hip.velocity) where v is given */
static void hip_point(sense_cache *kc, leg_sim *s, int leg, double *h, double *v, int *err) {
    int b = (int)s->leg_hip[leg], moved = (int)s->leg_hip_moved[leg];
    const double *p = pose(kc, s, b, moved, err);
    const double *pv = v ? velocity(kc, s, b, moved, err) : 0;
    const double *at = moved ? s->leg_hip_at + 3 * leg : 0;
    double a[3];
    leg_hip_point(p, at, h, a);
    if (v && !moved) /* the body origin's velocity, as it is */
        for (int k = 0; k < 3; k++) v[k] = pv[k];
    if (v && moved) { /* Hip.velocity: the body's, plus its turning about the hip's offset */
        const double *w = pv + 3;
        v[0] = pv[0] + (w[1] * a[2] - w[2] * a[1]);
        v[1] = pv[1] + (w[2] * a[0] - w[0] * a[2]);
        v[2] = pv[2] + (w[0] * a[1] - w[1] * a[0]);
    }
}

double leg_sense_leg(leg_sim *s, int leg, int member, int *err) {
    int foot = (int)s->leg_foot[leg];
    /* the leg's own clock, after the contacts': touching, touchdown, liftoff, stance, flight */
    const double *clock = s->clocks + 5 * (NC + leg);
    if (member == 0) return clock[0] != 0.0 ? 1.0 : 0.0;
    if (member == 1) return clock[3];
    if (member == 2) return clock[4];
    sense_cache *const kc = this_thread();
    feet(kc, s, err);
    const double *f = kc->foot + 3 * foot, *fv = kc->foot_v + 3 * foot;
    double h[3], hv[3];
    if (member == 3 || member == 4) {
        hip_point(kc, s, leg, h, hv, err);
        double d[3] = {f[0] - h[0], f[1] - h[1], f[2] - h[2]};
        double length = leg_sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        if (member == 3) return length;
        double dv[3] = {fv[0] - hv[0], fv[1] - hv[1], fv[2] - hv[2]};
        return length > 0 ? leg_div(d[0] * dv[0] + d[1] * dv[1] + d[2] * dv[2], length) : 0.0;
    }
    com(kc, s, err);
    if (member <= 7) {
        hip_point(kc, s, leg, h, 0, err);
        double rel[3] = {h[0] - kc->c[0], h[1] - kc->c[1], h[2] - kc->c[2]};
        return to_heading(kc, s, rel, member - 5, err);
    }
    if (member <= 10) {
        double rel[3] = {f[0] - kc->c[0], f[1] - kc->c[1], f[2] - kc->c[2]};
        return to_heading(kc, s, rel, member - 8, err);
    }
    double rel_v[3] = {fv[0] - kc->cv[0], fv[1] - kc->cv[1], fv[2] - kc->cv[2]};
    return to_heading(kc, s, rel_v, member - 11, err);
}

/* ------------------------------------------------------------ paths (path_tracking.py) */
/* path_data at path_at[k]: shape (0 none, 1 circle, 2 polyline), closed, cx, cy, radius, turn,
 * lookahead, length, n vertices, then x y per vertex, then their arclengths (PathGeometry's).
 * path_state: 12 per path: progress, last_s, then the 10 MEMBERS' values. */

/* Python's float %: the sign of the divisor (CPython's float_rem) */
static double py_mod(double x, double y, int *err) {
    if (y == 0.0) {
        leg_flag(err, LEG_EZERODIV);
        return NAN;
    }
    double mod = fmod(x, y);
    if (mod != 0.0) {
        if ((y < 0) != (mod < 0)) mod += y;
    } else {
        mod = copysign(0.0, y);
    }
    return mod;
}

static double wrap(double angle, int *err) { return atan2(leg_sin(angle), leg_cos(angle)); }

#define SAME_S 1e-9 /* path_tracking.SAME_S */

/* path_tracking._goes_on: whether arclength s goes on from last better than best, as near */
static int goes_on(double s, double best, double last) {
    int behind = s < last - SAME_S, best_behind = best < last - SAME_S;
    if (behind != best_behind) return best_behind;
    return fabs(s - last) < fabs(best - last) - SAME_S;
}

/* bisect.bisect_left (strict 0) or bisect_right (strict 1) of x in starts[0..n) + lap */
static int64_t bisect_starts(const double *starts, int64_t n, double lap, double x, int strict) {
    int64_t lo = 0, hi = n;
    while (lo < hi) {
        int64_t mid = lo + (hi - lo) / 2;
        double v = starts[mid] + lap;
        if (strict ? x < v : v >= x) hi = mid;
        else lo = mid + 1;
    }
    return lo;
}

/* PathGeometry._within: the segments [first, stop) that may reach into [lo, hi] + lap */
static void path_within(const double *starts, int64_t nv, double lo, double hi, double lap,
                        int64_t *first, int64_t *stop) {
    if (isnan(lo) || isnan(hi)) {
        *first = 0;
        *stop = nv - 1;
        return;
    }
    int64_t f = bisect_starts(starts, nv, lap, lo, 0) - 2;
    int64_t t = bisect_starts(starts, nv, lap, hi, 1) + 1;
    *first = f > 0 ? f : 0;
    *stop = t < nv - 1 ? t : nv - 1;
}

/* PathGeometry.project: s, x, y, heading, lateral; of a polyline, within [lo, hi] of
 * arclength (a closed one's unwrapped), ties to the one that goes on from last */
static void project(const double *g, double x, double y, double lo, double hi, double last,
                    double slack, double *out, int *err) {
    if (g[0] == 1.0) {
        double cx = g[2], cy = g[3], radius = g[4], turn = g[5];
        double dx = x - cx, dy = y - cy;
        double r = leg_hypot(dx, dy);
        double phi = r > 0 ? atan2(dy, dx) : 0.0;
        double start = leg_div(-turn * LEG_PI, 2.0);
        out[0] = py_mod((phi - start) * turn, 2 * LEG_PI, err) * radius;
        double heading = phi + leg_div(turn * LEG_PI, 2.0);
        out[4] = (radius - r) * turn;
        out[1] = cx + radius * leg_cos(phi);
        out[2] = cy + radius * leg_sin(phi);
        out[3] = wrap(heading, err);
        return;
    }
    int closed = g[1] != 0.0;
    int64_t nv = (int64_t)g[8];
    const double *v = g + 9, *starts = g + 9 + 2 * nv;
    double length = g[7];
    double laps[3] = {-length, 0.0, length};
    int nlaps = closed && hi - lo < INFINITY ? 3 : 1;
    double best_d = INFINITY;
    int found = 0;
    for (int k = 0; k < nlaps; k++) {
        double lap = nlaps == 3 ? laps[k] : 0.0;
        int64_t first, stop;
        path_within(starts, nv, lo, hi, lap, &first, &stop);
        for (int64_t i = first; i < stop; i++) {
            double start = starts[i] + lap, end = starts[i + 1] + lap;
            if (end < lo || start > hi) continue;
            const double *a = v + 2 * i, *b = v + 2 * i + 2;
            double ex = b[0] - a[0], ey = b[1] - a[1];
            double seg = leg_hypot(ex, ey);
            double ulo = start < lo ? leg_min(1.0, leg_div(lo - start, seg)) : 0.0;
            double uhi = end > hi ? leg_max(0.0, leg_div(hi - start, seg)) : 1.0;
            double u = leg_div((x - a[0]) * ex + (y - a[1]) * ey, seg * seg);
            u = leg_min(uhi, leg_max(ulo, u));
            double px = a[0] + u * ex, py = a[1] + u * ey;
            double d = leg_hypot(x - px, y - py);
            double s = start + u * seg;
            if (d < best_d - slack || (d <= best_d + 1e-12 && found && goes_on(s, out[0], last))) {
                best_d = d;
                found = 1;
                double tx = leg_div(ex, seg), ty = leg_div(ey, seg);
                double cross = tx * (y - py) - ty * (x - px);
                double lateral;
                if (!closed && ((i == 0 && u == 0.0) || (u == 1.0 && i == nv - 2))) lateral = cross;
                else lateral = d > 0 ? copysign(d, cross) : 0.0;
                out[0] = s;
                out[1] = px; out[2] = py; out[3] = atan2(ty, tx); out[4] = lateral;
            }
        }
    }
}

/* PathGeometry.at: x, y, heading at arclength s */
static void path_at_s(const double *g, double s, double *out, int *err) {
    if (g[0] == 1.0) {
        double cx = g[2], cy = g[3], radius = g[4], turn = g[5];
        double phi = leg_div(-turn * LEG_PI, 2.0) + leg_div(turn * s, radius);
        out[0] = cx + radius * leg_cos(phi);
        out[1] = cy + radius * leg_sin(phi);
        out[2] = wrap(phi + leg_div(turn * LEG_PI, 2.0), err);
        return;
    }
    double length = g[7];
    int64_t nv = (int64_t)g[8];
    const double *v = g + 9, *starts = g + 9 + 2 * nv;
    s = g[1] != 0.0 ? py_mod(s, length, err) : leg_min(leg_max(s, 0.0), length);
    int64_t i = 0; /* the segment s is on (bisect_right, as PathGeometry.at) */
    if (nv > 2 && s >= starts[1]) {
        i = bisect_starts(starts, nv, 0.0, s, 1) - 1;
        if (i > nv - 2) i = nv - 2;
    }
    const double *a = v + 2 * i, *b = v + 2 * i + 2;
    double seg = starts[i + 1] - starts[i];
    double u = leg_div(s - starts[i], seg);
    out[0] = a[0] + u * (b[0] - a[0]);
    out[1] = a[1] + u * (b[1] - a[1]);
    out[2] = atan2(b[1] - a[1], b[0] - a[0]);
}

/* PathTracker.update, once per tick, at the centre of mass */
double leg_sense_path(leg_sim *s, int k, int member, int *err) {
    const double *g = s->path_data + s->path_at[k];
    double *st = s->path_state + 12 * k;
    if (g[0] != 0.0 && !path_fresh[k]) {
        path_fresh[k] = 1;
        sense_cache *const kc = this_thread();
        com(kc, s, err);
        double p[5], ahead[3];
        double x = kc->c[0], y = kc->c[1], last = st[1], length = g[7];
        if (isnan(last)) { /* the first reading: the whole path's nearest, or an earlier as near */
            project(g, x, y, -INFINITY, INFINITY, NAN, g[6], p, err);
            st[0] = p[0];
        } else if (g[0] == 1.0) {
            project(g, x, y, -INFINITY, INFINITY, NAN, 1e-12, p, err);
            double ds = p[0] - last;
            ds = py_mod(ds + leg_div(length, 2.0), length, err) - leg_div(length, 2.0);
            st[0] += ds;
        } else { /* within a window about the last reading (PathTracker.update says why) */
            double reach = leg_hypot(x - st[2 + 4], y - st[2 + 5]);
            double lo = last - reach, hi = last + g[6] + reach;
            if (g[1] != 0.0 && !(hi - lo < length)) {
                lo = last - leg_div(length, 2.0);
                hi = last + leg_div(length, 2.0);
            }
            project(g, x, y, lo, hi, last, 1e-12, p, err);
            st[0] += p[0] - last;
            if (g[1] != 0.0) p[0] = py_mod(p[0], length, err);
        }
        st[1] = p[0];
        path_at_s(g, p[0] + g[6], ahead, err);
        double values[10] = {p[4], p[3], st[0], length, p[1], p[2], ahead[0], ahead[1], ahead[2], 1.0};
        for (int j = 0; j < 10; j++) st[2 + j] = values[j];
    }
    return st[2 + member];
}

/* ------------------------------------------------------------ place (FootPlacer.solve) */
#define PLACE_ITERATIONS 2 /* FootPlacer's default */
#define MAX_STEP 0.3

/* kinematics.solve_small: x with a x = b (a: n rows of n, row by row; b becomes x) by
 * Gaussian elimination with partial pivoting, each operation the Python's in its order;
 * 0, or 1 where a pivot is zero (Python's None: a singular pose). */
static int solve_small(int64_t n, double *a, double *b) {
    for (int64_t col = 0; col < n; col++) {
        int64_t p = col;
        for (int64_t r = col + 1; r < n; r++)
            if (fabs(a[r * n + col]) > fabs(a[p * n + col])) p = r;
        if (a[p * n + col] == 0.0) return 1;
        for (int64_t k = 0; k < n; k++) {
            double t = a[col * n + k];
            a[col * n + k] = a[p * n + k];
            a[p * n + k] = t;
        }
        double t = b[col];
        b[col] = b[p];
        b[p] = t;
        for (int64_t r = col + 1; r < n; r++) {
            double f = a[r * n + col] / a[col * n + col];
            for (int64_t k = col + 1; k < n; k++) a[r * n + k] = a[r * n + k] - f * a[col * n + k];
            b[r] = b[r] - f * b[col];
        }
    }
    for (int64_t col = n - 1; col >= 0; col--) {
        double total = b[col];
        for (int64_t k = col + 1; k < n; k++) total = total - a[col * n + k] * b[k];
        b[col] = total / a[col * n + col];
    }
    return 0;
}

/* The servos' setpoints that put the foot at goals from the hip; 0, or 1 where Python raises. */
static int place(leg_sim *s, const int64_t *pi, const double *pd, const double *goals) {
    int e = 0;
    int *err = &e;
    int64_t foot = pi[0], leg = pi[1], n = pi[2];
    int64_t hip = s->leg_hip[leg], moved = s->leg_hip_moved[leg];
    const double *at = moved ? s->leg_hip_at + 3 * leg : 0;
    const int64_t *rows = pi + 3, *servo = rows + n, *qi = servo + n, *vi = qi + n;
    const int64_t *limited = vi + n;
    const double *low = pd, *high = pd + n;
    if (n > 3) return 1;
    double q[LEG_NQ], guess[3], pose[12 * NB], pos[NCS], jac[3 * NC * LEG_NV + 1];
    for (int k = 0; k < LEG_NQ; k++) q[k] = s->q[k];
    for (int64_t k = 0; k < n; k++) {
        guess[k] = s->act_target[servo[k]];
        if (!isfinite(guess[k])) guess[k] = q[qi[k]];
        q[qi[k]] = guess[k];
    }
    /* Python computes every foot, body and Jacobian row; only this foot's position and rows,
     * the hip's position and the root's rotation are read, and the _some functions (dynamics_some.c)
     * compute those as the whole functions do, failing where they fail. */
    unsigned char feet[NCS], root_and_hip[2 * NB], hip_only[2 * NB];
    for (int i = 0; i < NC; i++) feet[i] = i == foot;
    for (int b = 0; b < 2 * NB; b++)
        root_and_hip[b] = hip_only[b] = b == 2 * hip || (moved && b == 2 * hip + 1);
    root_and_hip[1] = 1; /* the root body's rotation */
    double yaw = 0.0;
    int posed = 0; /* pose is of q as it is now (the first iteration's, which Python computes again) */
    if (!LEG_PLANAR) {
        body_poses_some(q, root_and_hip, pose, err);
        yaw = atan2(pose[3 + 3], pose[3 + 0]);
        posed = 1;
    }
    double c = leg_cos(yaw), sn = leg_sin(yaw);
    for (int it = 0; it < PLACE_ITERATIONS; it++) {
        contact_positions_some(q, feet, pos, err);
        if (!posed) body_poses_some(q, hip_only, pose, err);
        posed = 0;
        const double *f = pos + 3 * foot;
        double h[3], offset[3];
        leg_hip_point(pose + 12 * hip, at, h, offset);
        double delta[3] = {f[0] - h[0], f[1] - h[1], f[2] - h[2]};
        double rel[3] = {c * delta[0] + sn * delta[1], -sn * delta[0] + c * delta[1], delta[2]};
        double residual[3], a[9], b[3], world[3][3], heading[3][3];
        for (int64_t k = 0; k < n; k++) residual[k] = rel[rows[k]] - goals[k];
        contact_jacobians_some(q, feet, jac, err);
        const double *J = jac + 3 * LEG_NV * foot;
        for (int r = 0; r < 3; r++)
            for (int64_t k = 0; k < n; k++) world[r][k] = J[r * LEG_NV + vi[k]];
        for (int64_t k = 0; k < n; k++) {
            heading[0][k] = c * world[0][k] + sn * world[1][k];
            heading[1][k] = -sn * world[0][k] + c * world[1][k];
            heading[2][k] = world[2][k];
        }
        for (int64_t i = 0; i < n; i++) {
            for (int64_t k = 0; k < n; k++) a[i * n + k] = heading[rows[i]][k];
            b[i] = -residual[i];
        }
        if (solve_small(n, a, b)) break; /* a singular pose: the placer stops */
        for (int64_t k = 0; k < n; k++) {
            double step = b[k]; /* kinematics.clip_step */
            if (step < -MAX_STEP) step = -MAX_STEP;
            else if (step > MAX_STEP) step = MAX_STEP;
            guess[k] += step;
            q[qi[k]] = guess[k];
        }
    }
    for (int64_t k = 0; k < n; k++)
        if (limited[k]) guess[k] = leg_min(leg_max(guess[k], low[k]), high[k]);
    if (e) return 1;
    for (int64_t k = 0; k < n; k++) s->act_target[servo[k]] = guess[k];
    return 0;
}

/* ------------------------------------------------------------ the machine (StateMachine.__call__) */
static int all_finite(const double *x, int n) {
    for (int k = 0; k < n; k++)
        if (!isfinite(x[k])) return 0;
    return 1;
}

/* StateMachine._enter: 0, or 1 where Python would fault */
static int enter(leg_sim *s, const leg_controller *c, int64_t state, double t, const double *sens,
                 double *out) {
    int e = 0;
    s->ctl_state = state;
    s->ctl_entered_at = t;
    int64_t key = s->ctl_binding * c->n_states + state;
    c->entries[key](sens, s->ctl_inputs, s->ctl_params, s->ctl_records, 0.0, out, &e);
    if (e || !all_finite(out, (int)c->n_records)) return 1;
    for (int64_t k = 0; k < c->n_records; k++) s->ctl_records[k] = out[k];
    s->ctl_event_t[s->n_ctl_events] = t;
    s->ctl_event_state[s->n_ctl_events++] = state;
    return 0;
}

int64_t leg_control_tick(leg_sim *s) {
    const leg_controller *c = &leg_the_controller;
    if (!leg_has_c_controller || !all_finite(s->q, LEG_NQ) || !all_finite(s->v, LEG_NV))
        return LEG_CONTROL;
    int64_t ni = c->n_inputs, nr = c->n_records;
    double *sens = s->ctl_work, *out = sens + c->n_sensors + 1;
    double *saved = out + (nr > c->max_settings ? nr : c->max_settings) + 1;
    int64_t n_clocks = NC + s->n_legs; /* the contacts' clocks, then the legs' */
    double *acts = saved + nr + ni + 5 * n_clocks + 2 * ni;
    int64_t na = s->n_act;
    /* what this tick may change, to undo it if Python must take the tick */
    int64_t started = s->ctl_started, state = s->ctl_state, binding = s->ctl_binding;
    int64_t sched_pos = s->sched_pos, n_hist = s->n_hist, n_events = s->n_ctl_events;
    double entered_at = s->ctl_entered_at;
    memcpy(saved, s->ctl_records, sizeof(double) * nr);
    memcpy(saved + nr, s->ctl_inputs, sizeof(double) * ni);
    memcpy(saved + nr + ni, s->clocks, sizeof(double) * 5 * n_clocks);
    memcpy(saved + nr + ni + 5 * n_clocks, s->ctl_integral, sizeof(double) * 2 * ni);
    memcpy(acts, s->act_gain, sizeof(double) * na);
    memcpy(acts + na, s->act_damping, sizeof(double) * na);
    memcpy(acts + 2 * na, s->act_target, sizeof(double) * na);
    memcpy(acts + 3 * na, s->act_force, sizeof(double) * na);
    double t = s->t;
    int e = 0;
    int *err = &e;
    int changed = 0; /* _apply_schedule */
    while (s->sched_pos < s->sched_n && s->sched_t[s->sched_pos] <= t + 1e-12) {
        int64_t i = s->sched_input[s->sched_pos];
        double now = s->sched_value[s->sched_pos], *integral = s->ctl_integral + 2 * i;
        if (now != s->ctl_inputs[i]) { /* Integral.change */
            integral[0] += s->ctl_inputs[i] * (t - integral[1]);
            integral[1] = t;
        }
        s->ctl_inputs[i] = now;
        s->sched_pos++;
        changed = 1;
    }
    if (changed) {
        s->hist_t[s->n_hist] = t;
        memcpy(s->hist_inputs + s->n_hist * ni, s->ctl_inputs, sizeof(double) * ni);
        s->n_hist++;
    }
    for (int64_t i = 0; i < n_clocks; i++) { /* Sensors.observe: each contact, then each leg */
        double *clock = s->clocks + 5 * i;
        int now = 0;
        if (i < NC) {
            now = s->has_ground && s->touching[i];
        } else { /* a leg touches while any of its soles does */
            for (int k = 0; k < NC; k++)
                now |= s->leg_soles[(i - NC) * NC + k] && s->has_ground && s->touching[k];
        }
        if (now && clock[0] == 0.0) {
            if (!isnan(clock[2])) clock[4] = t - clock[2];
            clock[1] = t;
        } else if (clock[0] != 0.0 && !now) {
            if (!isnan(clock[1])) clock[3] = t - clock[1];
            clock[2] = t;
        }
        clock[0] = now ? 1.0 : 0.0;
    }
    leg_sense_begin();
    c->read_sensors(s, sens, err);
    if (e) goto python;
    if (!s->ctl_started) {
        s->ctl_started = 1;
        if (enter(s, c, s->ctl_state, t, sens, out)) goto python;
    } else {
        int64_t next = (s->ctl_state + 1) % c->n_states;
        int64_t key = s->ctl_binding * c->n_states + next;
        double tis = t - s->ctl_entered_at;
        int fire = c->events[key](sens, s->ctl_inputs, s->ctl_params, s->ctl_records, tis, err);
        if (e) goto python;
        if (fire) {
            s->ctl_binding = c->after_entry[key];
            if (enter(s, c, next, t, sens, out)) goto python;
        }
    }
    {
        int64_t key = s->ctl_binding * c->n_states + s->ctl_state;
        double tis = t - s->ctl_entered_at;
        c->actions[key](sens, s->ctl_inputs, s->ctl_params, s->ctl_records, tis, out, err);
        int64_t n = c->n_settings[key];
        if (e || !all_finite(out, (int)c->n_outputs[key])) goto python;
        const int64_t *targets = c->settings[key];
        for (int64_t k = 0; k < n; k++) {
            int64_t a = targets[2 * k];
            /* a negative stiffness or damping: Python's machine says why the run stops */
            if (out[k] < 0.0 && targets[2 * k + 1] <= LEG_SET_DAMPING) goto python;
            switch (targets[2 * k + 1]) {
            case LEG_SET_GAIN: s->act_gain[a] = out[k]; break;
            case LEG_SET_DAMPING: s->act_damping[a] = out[k]; break;
            case LEG_SET_TARGET: s->act_target[a] = out[k]; break;
            default: s->act_force[a] = out[k]; break;
            }
        }
        const double *goals = out + n;
        for (int64_t k = 0; k < c->n_places[key]; k++) {
            const int64_t *pi = c->places_i[key] + 0;
            const double *pd = c->places_d[key] + 0;
            for (int64_t j = 0; j < k; j++) { /* the k-th place of this (binding, state) */
                pd += 2 * pi[2];
                pi += 3 + 5 * pi[2];
            }
            if (place(s, pi, pd, goals)) goto python;
            goals += pi[2];
        }
    }
    s->state_index = s->state_offset + s->ctl_state; /* a switching run's numbering */
    s->speed_command = s->speed_input >= 0 ? s->ctl_inputs[s->speed_input] : NAN;
    s->ctl_ticks++;
    return 0;
python: /* undo the tick: Python's state machine takes it from the same state */
    s->ctl_started = started; s->ctl_state = state; s->ctl_binding = binding;
    s->ctl_entered_at = entered_at;
    s->sched_pos = sched_pos; s->n_hist = n_hist; s->n_ctl_events = n_events;
    memcpy(s->ctl_records, saved, sizeof(double) * nr);
    memcpy(s->ctl_inputs, saved + nr, sizeof(double) * ni);
    memcpy(s->clocks, saved + nr + ni, sizeof(double) * 5 * n_clocks);
    memcpy(s->ctl_integral, saved + nr + ni + 5 * n_clocks, sizeof(double) * 2 * ni);
    memcpy(s->act_gain, acts, sizeof(double) * na);
    memcpy(s->act_damping, acts + na, sizeof(double) * na);
    memcpy(s->act_target, acts + 2 * na, sizeof(double) * na);
    memcpy(s->act_force, acts + 3 * na, sizeof(double) * na);
    return LEG_CONTROL;
}

/* ------------------------------------------------------------ the terrain ahead */
/* Sensors._terrain and terrain_ahead.ahead: member 0 ahead_distance, 1 ahead_height,
 * 2 ahead_depth, 3 ahead_given, 4 height (under the centre of mass). Only steps and boxes
 * are features ahead (s->flats holds them in the terrain's order; a slope is never one). */
double leg_sense_terrain(leg_sim *s, int member, int *err) {
    sense_cache *const kc = this_thread();
    com(kc, s, err);
    double x = kc->c[0], y = kc->c[1];
    if (member == 4) return s->has_ground ? leg_ground_height(s, x, y, err) : 0.0;
    heading(kc, s, err);
    double yaw = atan2(kc->hs, kc->hc);
    double c = leg_cos(yaw), sn = leg_sin(yaw);
    int found = 0;
    double best[3] = {0.0, 0.0, 0.0}; /* distance, depth, height */
    for (int64_t k = 0; s->has_ground && k < s->n_flats; k++) {
        const double *f = s->flats + 6 * k; /* x, x0, x1, y0, y1, height */
        double hit[2];
        if (!s->flat_is_box[k]) {
            if (c <= 0.0 || x >= f[0]) continue;
            hit[0] = (f[0] - x) / c;
            hit[1] = 0.0;
        } else {
            double enter = -INFINITY, leave = INFINITY;
            double p[2] = {x, y}, d[2] = {c, sn}, lo[2] = {f[1], f[3]}, hi[2] = {f[2], f[4]};
            int miss = 0;
            for (int i = 0; i < 2; i++) {
                if (fabs(d[i]) < 1e-12) {
                    if (!(lo[i] <= p[i] && p[i] <= hi[i])) { miss = 1; break; }
                    continue;
                }
                double a = (lo[i] - p[i]) / d[i], b = (hi[i] - p[i]) / d[i];
                enter = leg_max(enter, leg_min(a, b));
                leave = leg_min(leave, leg_max(a, b));
            }
            if (miss || enter <= 0.0 || leave < enter) continue;
            hit[0] = enter;
            hit[1] = leave - enter;
        }
        if (!found || hit[0] < best[0]) {
            found = 1;
            best[0] = hit[0]; best[1] = hit[1]; best[2] = f[5];
        }
    }
    if (!found) return 0.0;
    return member == 0 ? best[0] : member == 1 ? best[2] : member == 2 ? best[1] : 1.0;
}
