/* legdsl_control.h: what a generated control_CONTROLLER.c gives the state machine (machine.c).
 *
 * The generated file holds the controller's event, entry and action functions (printed from
 * the same straight-line code as control_CONTROLLER.py) and the tables of machine.py:
 * AFTER_ENTRY, EVENTS, ENTRIES, ACTIONS, SETTINGS, indexed by binding * n_states + state.
 * Its read_sensors computes the SENSORS in order with the functions below (sensors.py).
 */
#ifndef LEGDSL_CONTROL_H
#define LEGDSL_CONTROL_H

#include <stdint.h>
#include "legdsl_sim.h"

typedef int (*leg_event_fn)(const double *s, const double *u, const double *p, const double *r,
                            double tis, int *err);
typedef void (*leg_values_fn)(const double *s, const double *u, const double *p,
                              const double *r, double tis, double *out, int *err);

/* what a setting sets on its actuator (ActuatorState.set) */
enum { LEG_SET_GAIN = 0, LEG_SET_DAMPING = 1, LEG_SET_TARGET = 2, LEG_SET_FORCE = 3 };

typedef struct {
    int64_t n_states, n_bindings, n_sensors, n_inputs, n_records, max_settings;
    const int64_t *after_entry;
    const leg_event_fn *events;
    const leg_values_fn *entries;
    const leg_values_fn *actions;
    const int64_t *n_settings;
    const int64_t *const *settings; /* per (binding, state): (actuator, LEG_SET_*) pairs */
    void (*read_sensors)(leg_sim *s, double *out, int *err);
    const int64_t *n_outputs;         /* per (binding, state): settings, then the place goals */
    const int64_t *n_places;          /* per (binding, state) */
    const int64_t *const *places_i;   /* per place: foot, leg, n, rows[n], servo[n], q[n], v[n], limited[n] */
    const double *const *places_d;    /* per place: low[n], high[n] */
} leg_controller;

extern const leg_controller leg_the_controller;

/* Sensors (legdsl/sim/sensors.py), computed from the state now; kinematics cached per tick. */
void leg_sense_begin(void);
double leg_sense_com(leg_sim *s, int axis, int velocity, int *err);
double leg_sense_contact(leg_sim *s, int contact, int member, int *err);
double leg_sense_act(const leg_sim *s, int actuator, int member);
double leg_sense_body(leg_sim *s, int body, int member, int *err);
double leg_sense_leg(leg_sim *s, int leg, int member, int *err);
double leg_sense_path(leg_sim *s, int path, int member, int *err);
double leg_sense_terrain(leg_sim *s, int member, int *err);
double leg_ground_height(const leg_sim *s, double x, double y, int *err);

/* contact members: 0 touching, 1-3 x y z, 4-6 vx vy vz */
/* actuator members: 0 gain (k, kp), 1 damping (b, kv), 2 target (rest, setpoint), 3 force */
/* body members: 0-2 x y z, 3-5 vx vy vz, 6 roll, 7 pitch, 8 yaw, 9-11 their rates */
/* path members: MEMBERS of legdsl/ir/paths.py, in order (lateral ... given) */
/* leg members: 0 touching, 1 stance_time, 2 flight_time, 3 length, 4 rate, 5-7 hip_x y z,
 * 8-10 foot_x y z, 11-13 foot_vx vy vz */

#endif
