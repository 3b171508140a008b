/* A free target in the loop of contact through the C stepper (run by scripts/c-tests.sh from the
 * repository root, also under AddressSanitizer and UBSan; docs/c-api.md, "A free target"): the
 * options file tests/c/target/options.toml names the target's model file (rock.toml, read from
 * the options file's folder) and its 13-state; the rock comes at the arm's tip, the contact
 * stops it and pushes the robot back. Checked: the rock's momentum changed (the contact acted), and
 * robot + rock keep their linear and angular momentum (robot's from spacearm_momentum, rock's
 * from its state, mass and inertia: m v, r x m v + R I R^T w) while the contact forces, equal
 * and opposite, act. Then the errors: a stepper without a target, a target without its state, a
 * URDF target file, an FMU's refusal. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "spacearm.h"
#include "check.h"

#define DIR "crates/spacearm-c/tests/c/target/"
#define NX 8
#define NU 7

/* The rock of rock.toml: mass and principal moments (its body axes). */
static const double M_ROCK = 2.0, I_ROCK[3] = {0.08, 0.1, 0.12};

/* Robot + rock [P; L about the origin] at (x, u) and the rock's 13-state s. */
static void total_momentum(const SpacearmModel *m, const double *x, const double *u, const double *s, double *h) {
    double robot[9];
    OK(spacearm_momentum(m, x, u, robot));
    /* R from the quaternion [x, y, z, w]; L_rock = r x m v + R I R^T w. */
    double qx = s[3], qy = s[4], qz = s[5], qw = s[6];
    double R[3][3] = {{1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw)},
                      {2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw)},
                      {2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy)}};
    double wb[3], spin[3];
    for (int i = 0; i < 3; i++) wb[i] = R[0][i] * s[10] + R[1][i] * s[11] + R[2][i] * s[12];
    for (int i = 0; i < 3; i++) spin[i] = R[i][0] * I_ROCK[0] * wb[0] + R[i][1] * I_ROCK[1] * wb[1] + R[i][2] * I_ROCK[2] * wb[2];
    double p[3] = {M_ROCK * s[7], M_ROCK * s[8], M_ROCK * s[9]};
    double rxp[3] = {s[1] * p[2] - s[2] * p[1], s[2] * p[0] - s[0] * p[2], s[0] * p[1] - s[1] * p[0]};
    for (int i = 0; i < 3; i++) {
        h[i] = robot[i] + p[i];
        h[3 + i] = robot[3 + i] + rxp[i] + spin[i];
    }
}

int main(void) {
    SpacearmModel *m = NULL;
    OK(spacearm_model_from_toml_file(DIR "robot.toml", &m));
    if (!m) return FAILED();
    SpacearmStepper *s = NULL;
    OK(spacearm_stepper_new_from_file(m, DIR "options.toml", &s));
    if (!s) return FAILED();
    double x[NX] = {0, 0, 0, 0, 0, 0, 1, 0}, u[NU] = {0.01, 0, 0, 0, 0, 0.005, 0}, st[13];
    OK(spacearm_stepper_reset(s, x, u));
    OK(spacearm_stepper_target_state(s, st));
    CHECK(st[0] == 1.45 && st[7] == -0.1, "the options' 13-state: r_x %g, v_x %g", st[0], st[7]);
    double h0[6], h[6], v0 = st[7];
    total_momentum(m, x, u, st, h0);
    double worst = 0.0, scale = 0.0;
    for (int i = 0; i < 6; i++) scale = fmax(scale, fabs(h0[i]));
    /* 1 s in 16 calls of 64 steps: the rock reaches the tip at about 0.45 s */
    for (int k = 0; k < 16; k++) {
        OK(spacearm_stepper_step(s, NULL, NULL, 64));
        OK(spacearm_stepper_state(s, x, u));
        OK(spacearm_stepper_target_state(s, st));
        total_momentum(m, x, u, st, h);
        for (int i = 0; i < 6; i++) worst = fmax(worst, fabs(h[i] - h0[i]));
    }
    CHECK(fabs(spacearm_stepper_time(s) - 1.0) < 1e-15, "t = %.17g", spacearm_stepper_time(s));
    CHECK(st[7] - v0 > 0.05, "the contact stopped the rock: v_x %g -> %g", v0, st[7]);
    /* the contact forces are internal: what drifts is the RK4 error of the contact's fast motion (5e-10 here) */
    CHECK(worst < 1e-8 * scale, "robot + rock momentum drifts by %.3g (scale %.3g)", worst, scale);
    spacearm_stepper_free(s);

    /* a stepper without a target has no target state */
    s = NULL;
    OK(spacearm_stepper_new(m, "dt = 0.001\n", &s));
    OK(spacearm_stepper_reset(s, (double[NX]){0, 0, 0, 0, 0, 0, 1, 0}, (double[NU]){0}));
    CHECK(spacearm_stepper_target_state(s, st) == SPACEARM_STATUS_INVALID_ARGUMENT && strstr(spacearm_last_error(), "no free target"), "%s",
          spacearm_last_error());
    spacearm_stepper_free(s);
    /* a target without its state, a URDF file: refused with their reasons */
    s = NULL;
    SpacearmStatus e = spacearm_stepper_new(m, "target = \"" DIR "rock.toml\"\n[contact]\nstiffness = 1e4\n", &s);
    CHECK(e == SPACEARM_STATUS_INVALID_ARGUMENT && strstr(spacearm_last_error(), "target and target_state go together"), "%s", spacearm_last_error());
    e = spacearm_stepper_new(m, "target = \"rock.urdf\"\ntarget_state = [0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0]\n[contact]\nstiffness = 1e4\n", &s);
    CHECK(e == SPACEARM_STATUS_INVALID_ARGUMENT && strstr(spacearm_last_error(), "URDF"), "%s", spacearm_last_error());
    /* a target without contact: the target takes part by contact */
    e = spacearm_stepper_new(m, "target = \"" DIR "rock.toml\"\ntarget_state = [2, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0]\n", &s);
    CHECK(e == SPACEARM_STATUS_INVALID_ARGUMENT && strstr(spacearm_last_error(), "by contact"), "%s", spacearm_last_error());
    CHECK(s == NULL, "no stepper made");
    spacearm_model_free(m);
    if (FAILED()) return 1;
    printf("spacearm C free-target tests passed (momentum drift %.2g of %.2g)\n", worst, scale);
    return 0;
}
