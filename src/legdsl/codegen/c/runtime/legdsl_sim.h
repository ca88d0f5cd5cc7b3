/* legdsl_sim.h: the state a run shares between Python and the C runtime (legdsl's C backend).
 *
 * Every field of leg_sim is listed once, in LEG_SIM_FIELDS: step.c exports the list as text
 * (leg_sim_fields) and legdsl/sim/c_library.py builds its ctypes twin from it, so the two
 * layouts cannot differ. Arrays are owned by Python (numpy) and only pointed to.
 */
#ifndef LEGDSL_SIM_H
#define LEGDSL_SIM_H

#include <stdint.h>

#define LEG_SIM_FIELDS(X) \
    X(double, dt) X(int64_t, rk4) X(int64_t, n_steps) X(int64_t, control_every) \
    X(int64_t, check_every) X(int64_t, has_controller) X(int64_t, record_every) X(int64_t, capacity) \
    X(int64_t, has_fall_height) X(double, fall_height) X(double, fall_tilt) \
    X(double, start_height) X(double, size_scale) X(double *, v_factor) X(int64_t, step_budget) \
    X(int64_t, steps) X(int64_t, phase) X(int64_t, steps_taken) X(double, t) \
    X(int64_t, recorded) X(int64_t, rows) \
    X(double *, q) X(double *, v) \
    X(int64_t, n_act) X(int64_t *, act_is_force) X(int64_t *, act_qi) X(int64_t *, act_vi) \
    X(int64_t *, act_has_limit) X(double *, act_gain) X(double *, act_damping) \
    X(double *, act_target) X(double *, act_force) X(double *, act_limit) X(double *, act_last) \
    X(int64_t, n_stops) X(int64_t *, stop_qi) X(int64_t *, stop_vi) X(double *, stop_low) \
    X(double *, stop_high) X(double *, stop_k) X(double *, stop_b) X(double *, stop_time) \
    X(int64_t, has_ground) X(int64_t, normal_pad) X(double, normal_k) X(double, normal_b) \
    X(double, pad_thickness) X(double, tangent_k) X(double, tangent_b) \
    X(int64_t, has_friction) X(double, friction) X(int64_t, torsion) X(double, torsion_k) \
    X(double, torsion_b) X(int64_t, has_slope) X(double, slope_angle) X(int64_t, n_flats) \
    X(int64_t *, flat_is_box) X(double *, flats) \
    X(int64_t *, contact_body) X(int64_t *, touching) X(double *, anchor) \
    X(double *, yaw_anchor) X(int64_t *, slipping) X(double *, contact_force) \
    X(int64_t, n_events) X(int64_t, event_cap) X(double *, event_t) X(int64_t *, event_kind) \
    X(int64_t *, event_contact) \
    X(int64_t, n_legs) X(int64_t *, leg_hip) X(int64_t *, leg_hip_moved) X(double *, leg_hip_at) \
    X(int64_t *, leg_foot) X(int64_t *, leg_soles) X(int64_t *, leg_spring) \
    X(int64_t, state_index) X(int64_t, state_offset) X(double, speed_command) \
    X(double *, rec_t) X(double *, rec_q) X(double *, rec_v) X(int8_t *, rec_contact) \
    X(double *, rec_force) X(double *, rec_com) X(double *, rec_com_vel) \
    X(double *, rec_root_pos) X(double *, rec_root_rpy) X(double *, rec_leg_length) \
    X(double *, rec_leg_spring_energy) X(double *, rec_kinetic) X(double *, rec_potential) \
    X(double *, rec_elastic) X(int16_t *, rec_state) X(double *, rec_speed_command) \
    X(int64_t, err) \
    X(int64_t, c_control) X(double, ctl_command_at) X(double, ctl_switch_at) \
    X(double, ctl_switch_until) X(int64_t, ctl_started) X(int64_t, ctl_state) \
    X(int64_t, ctl_binding) X(double, ctl_entered_at) X(double *, ctl_records) \
    X(double *, ctl_inputs) X(double *, ctl_integral) \
    X(double *, ctl_params) X(int64_t, sched_n) X(int64_t, sched_pos) X(double *, sched_t) \
    X(int64_t *, sched_input) X(double *, sched_value) X(int64_t, n_hist) X(double *, hist_t) \
    X(double *, hist_inputs) X(int64_t, speed_input) X(double *, clocks) \
    X(int64_t, n_ctl_events) X(double *, ctl_event_t) X(int64_t *, ctl_event_state) \
    X(double *, ctl_work) X(int64_t, ctl_ticks) \
    X(int64_t, n_paths) X(int64_t *, path_at) X(double *, path_data) X(double *, path_state) \
    X(int64_t, kin_valid) X(double *, kin) \
    X(double *, act_work) X(double *, rec_work_positive) X(double *, rec_work_negative)

#define LEG_DECLARE(type, name) type name;
typedef struct { LEG_SIM_FIELDS(LEG_DECLARE) } leg_sim;

/* What leg_run returns: why it handed control back to Python. */
enum {
    LEG_DONE = 0,         /* the last step was taken */
    LEG_CONTROL = 1,      /* the controller is due (call it, then leg_run again) */
    LEG_FULL = 2,         /* the recording buffers are full (grow them, then leg_run again) */
    LEG_YIELD = 3,        /* the step budget of one call is spent, or the events buffer is full */
    LEG_CHECK = 4,        /* the fall and divergence check failed (Python says how) */
    LEG_NONFINITE = 5,    /* the state is no longer finite at a recorded instant */
    LEG_RAISED = 6,       /* Python would have raised: sim->err says what */
    LEG_STOPPED = 7       /* a batch's copy stopped because the batch was told to (batch.c) */
};

/* The controller, when it runs in C (machine.c; the generated control_CONTROLLER.c). */
int64_t leg_control_tick(leg_sim *s);  /* 0, or LEG_CONTROL: Python must take this tick */
extern const int64_t leg_has_c_controller;

/* The kinematics both the step and the sensors use (step.c). */
double leg_dist3(const double *p, const double *q);
double leg_hypot(double x, double y);

/* Where a leg's hip point h is, from the pose of its body (origin, then the row-major
 * rotation) and, for a leg that starts with a slide, the joint's place in that body (at; 0 for
 * the body's origin itself): ir.model.Hip.point. a is the offset turned into the world. */
static inline void leg_hip_point(const double *pose, const double *at, double *h, double *a) {
    const double *r = pose + 3;
    for (int k = 0; k < 3; k++) {
        a[k] = at ? r[3 * k] * at[0] + r[3 * k + 1] * at[1] + r[3 * k + 2] * at[2] : 0.0;
        h[k] = at ? pose[k] + a[k] : pose[k];
    }
}

#endif
