/* legdsl_model.h: the functions of a creature's dynamics that the C runtime calls.
 *
 * The generated dynamics.c and dynamics_some.c define them; their dynamics.h includes this
 * file, so the compiler checks that the two declarations agree. The runtime (step.c,
 * machine.c, batch.c) includes this and legdsl_sizes.h, never a creature's dynamics.h: the
 * build writes legdsl_sizes.h from dynamics.h's sizes (codegen/c/build.py), so every creature
 * of the same sizes shares the runtime's objects in the cache, while the sizes stay constants
 * the compiler folds into the step's loops.
 */
#ifndef LEGDSL_MODEL_H
#define LEGDSL_MODEL_H

void mass_matrix(const double *q, double *out, int *err);
void bias_forces(const double *q, const double *v, double *out, int *err);
void forward_dynamics(const double *q, const double *v, const double *tau, double *out, int *err);
void contact_positions(const double *q, double *out, int *err);
void contact_positions_some(const double *q, const unsigned char *want, double *out, int *err);
void contact_velocities(const double *q, const double *v, double *out, int *err);
void contact_velocities_some(const double *q, const double *v, const unsigned char *want,
                             double *out, int *err);
void contact_jacobians(const double *q, double *out, int *err);
void contact_jacobians_some(const double *q, const unsigned char *want, double *out, int *err);
void contact_angular_jacobians(const double *q, double *out, int *err);
void contact_angular_jacobians_some(const double *q, const unsigned char *want, double *out,
                                    int *err);
void body_poses(const double *q, double *out, int *err);
void body_poses_some(const double *q, const unsigned char *want, double *out, int *err);
void body_velocities(const double *q, const double *v, double *out, int *err);
void body_velocities_some(const double *q, const double *v, const unsigned char *want,
                          double *out, int *err);
void center_of_mass(const double *q, double *out, int *err);
void center_of_mass_velocity(const double *q, const double *v, double *out, int *err);
void kinetic_energy(const double *q, const double *v, double *out, int *err);
void potential_energy(const double *q, double *out, int *err);

#endif
