/* A worked example of the spacearm C ABI (docs/c-api.md): load a model, compute the generalized
 * inertia H* and the generalized Jacobian J* of the end effector, then step a floating
 * simulation with a held joint torque and print the base attitude it ends with.
 *
 *   cargo build --release -p spacearm-c
 *   cc -I crates/spacearm-c/include crates/spacearm-c/examples/example.c \
 *      target/release/libspacearm_c.a -lpthread -ldl -lm -o example && ./example
 */
#include <stdio.h>
#include <stdlib.h>

#include "spacearm.h"

/* Print the message of a failed call and exit. */
static void check(SpacearmStatus status, const char *what) {
    if (status != SPACEARM_STATUS_OK) {
        fprintf(stderr, "%s failed (%s): %s\n", what, spacearm_status_name(status), spacearm_last_error());
        exit(1);
    }
}

int main(void) {
    SpacearmModel *model = NULL;
    check(spacearm_model_preset("spatial6", &model), "spacearm_model_preset");
    size_t n = spacearm_model_n_dof(model), nx = spacearm_model_nx(model), nu = spacearm_model_nu(model);
    double *x = malloc(nx * sizeof *x), *u = calloc(nu, sizeof *u);
    double *hs = malloc(n * n * sizeof *hs), *js = malloc(6 * n * sizeof *js);
    check(spacearm_model_initial_configuration(model, x), "spacearm_model_initial_configuration");

    /* H* (N x N, row-major): element (i, j) is hs[i * n + j]. */
    check(spacearm_generalized_inertia(model, x, hs), "spacearm_generalized_inertia");
    printf("H* of %zu joints, diagonal:", n);
    for (size_t i = 0; i < n; i++) printf(" %.4f", hs[i * n + i]);
    printf("\n");

    /* J* of the end effector (6 x N, linear rows first). */
    size_t body;
    double offset[3];
    check(spacearm_model_point(model, NULL, &body, offset), "spacearm_model_point");
    check(spacearm_generalized_jacobian(model, x, body, offset, js), "spacearm_generalized_jacobian");
    printf("J* row 0:");
    for (size_t j = 0; j < n; j++) printf(" %.4f", js[j]);
    printf("\n");

    /* One second of free floating with a constant torque on joint 1 (RK4, 1 ms steps). */
    SpacearmStepper *sim = NULL;
    check(spacearm_stepper_new(model, "mode = \"floating\"\ndt = 0.001\n", &sim), "spacearm_stepper_new");
    check(spacearm_stepper_reset(sim, x, u), "spacearm_stepper_reset");
    double *tau = calloc(n, sizeof *tau);
    tau[0] = 1.0;
    check(spacearm_stepper_step(sim, tau, NULL, 1000), "spacearm_stepper_step");
    check(spacearm_stepper_state(sim, x, u), "spacearm_stepper_state");
    printf("t = %.3f s: base quaternion [%.6f, %.6f, %.6f, %.6f], q1 = %.6f rad\n", spacearm_stepper_time(sim), x[3], x[4], x[5],
           x[6], x[7]);

    spacearm_stepper_free(sim);
    spacearm_model_free(model);
    free(x), free(u), free(hs), free(js), free(tau);
    return 0;
}
