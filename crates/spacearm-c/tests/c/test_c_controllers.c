/* The native controllers of the C stepper (run by scripts/c-tests.sh from the repository root,
 * also under AddressSanitizer and UBSan): the options' [controller] table is the core's
 * ControllerSpec (docs/c-api.md, "Controllers"). One test per native law: the options parse, the
 * stepper runs, and the state moves as the law demands, checked against a closed form where the
 * closed loop has one (computed torque: e = e0 (1 + w t) exp(-w t); thruster regulation of the
 * CM: P = P0 (1 - t) exp(-t); momentum damping: P, L_cm = (P0, L_cm0) exp(-t / tau)), against a
 * constant-torque run where the law is a clamp (torque_limit), else by the error it must shrink.
 * Then the errors: an unknown kind or field is PARSE, a bad value the core's status, each with a
 * message naming what was wrong. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "spacearm.h"
#include "check.h"

/* The model with three reaction wheels (the rotation-floating example of the Python package). */
#define WHEELS_MODEL "python/spacearm/examples/spatial6_wheels.toml"
#define MAXN 16

/* Run `options` on `m` from (x0, u0) for n steps with the held torque `tau` (NULL: none); the
 * final state into (x, u). Returns the status of the first call that failed. */
static SpacearmStatus run(const SpacearmModel *m, const char *options, const double *x0, const double *u0, const double *tau, size_t n, double *x,
                          double *u) {
    SpacearmStepper *s = NULL;
    SpacearmStatus st = spacearm_stepper_new(m, options, &s);
    if (st != SPACEARM_STATUS_OK) return st;
    if ((st = spacearm_stepper_reset(s, x0, u0)) == SPACEARM_STATUS_OK && (st = spacearm_stepper_step(s, tau, NULL, n)) == SPACEARM_STATUS_OK)
        st = spacearm_stepper_state(s, x, u);
    spacearm_stepper_free(s);
    return st;
}

static double norm3(const double *v) { return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

static double dist3(const double *a, const double *b) {
    double d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
    return norm3(d);
}

/* The end effector's position at x. */
static void ee_position(const SpacearmModel *m, const double *x, double *p) {
    size_t body;
    double off[3];
    OK(spacearm_model_point(m, NULL, &body, off));
    OK(spacearm_point_pose(m, x, body, off, p, NULL));
}

/* The angle of the rotation from quaternion a to b ([x, y, z, w]), rad. */
static double angle_between(const double *a, const double *b) {
    double dot = fabs(a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]);
    return 2.0 * acos(dot > 1.0 ? 1.0 : dot);
}

static SpacearmModel *preset(const char *name) {
    SpacearmModel *m = NULL;
    OK(spacearm_model_preset(name, &m));
    return m;
}

static SpacearmModel *wheels_model(void) {
    SpacearmModel *m = NULL;
    OK(spacearm_model_from_toml_file(WHEELS_MODEL, &m));
    return m;
}

/* A list "[a, b, ...]" of n numbers, written to round-trip. */
static void list(char *buf, const double *v, size_t n) {
    size_t k = (size_t)sprintf(buf, "[");
    for (size_t i = 0; i < n; i++) k += (size_t)sprintf(buf + k, "%s%.17g", i ? ", " : "", v[i]);
    sprintf(buf + k, "]");
}

/* Options `head` then `key` = a line of the end effector from its position at x0 (into p0) to
 * p0 + delta (into goal) over t in [0, 1] s: the reference of the Cartesian laws. */
static void line_options(char *opts, size_t size, const SpacearmModel *m, const double *x0, const double *delta, const char *head, const char *key,
                         double *p0, double *goal) {
    char a[256], b[256];
    ee_position(m, x0, p0);
    for (int i = 0; i < 3; i++) goal[i] = p0[i] + delta[i];
    list(a, p0, 3);
    list(b, goal, 3);
    snprintf(opts, size, "%s%s = { kind = \"line\", p_start = %s, p_goal = %s, t_start = 0.0, t_end = 1.0 }\n", head, key, a, b);
}

/* kind = "none": only the held torque acts; the same run as no [controller] table, bit for
 * bit, and a robot at rest stays exactly at rest. */
static void test_none(void) {
    SpacearmModel *m = preset("spatial6");
    double x0[13], u0[12] = {0}, x[13], u[12], x2[13], u2[12], tau[6] = {1, -1, 0.5, 0.2, -0.1, 0.1};
    OK(spacearm_model_initial_configuration(m, x0));
    OK(run(m, "dt = 0.002\n[controller]\nkind = \"none\"\n", x0, u0, tau, 100, x, u));
    OK(run(m, "dt = 0.002\n", x0, u0, tau, 100, x2, u2));
    CHECK(memcmp(x, x2, sizeof x) == 0 && memcmp(u, u2, sizeof u) == 0, "none differs from no controller");
    CHECK(fabs(u[6]) > 1e-3, "the held torque did not act");
    OK(run(m, "dt = 0.002\n[controller]\nkind = \"none\"\n", x0, u0, NULL, 100, x, u));
    CHECK(memcmp(x, x0, sizeof x) == 0, "a robot at rest without torque moved");
    spacearm_model_free(m);
}

/* Run the joint-space law `law` (the options up to its gains; the reference is appended) on
 * spatial6 from rest at its initial configuration (into x0) toward the set point
 * ref[i] = x0[7 + i] + step[i] for n steps; the final configuration into x. */
static void run_to_set_point(const char *law, const double *step, size_t n, double *x0, double *ref, double *x) {
    SpacearmModel *m = preset("spatial6");
    double u0[12] = {0}, u[12];
    char r[512], opts[1024];
    OK(spacearm_model_initial_configuration(m, x0));
    for (int i = 0; i < 6; i++) ref[i] = x0[7 + i] + step[i];
    list(r, ref, 6);
    snprintf(opts, sizeof opts, "%sreference = %s\n", law, r);
    OK(run(m, opts, x0, u0, NULL, n, x, u));
    spacearm_model_free(m);
}

/* joint_pd: the joints go to the set point (the error shrinks to a few percent in 3 s, and the
 * base turns: joint torques are internal). */
static void test_joint_pd(void) {
    double x0[13], x[13], ref[6], step[6], e0 = 0.0, e = 0.0;
    for (int i = 0; i < 6; i++) step[i] = 0.1 * (i % 2 ? -1 : 1);
    run_to_set_point("dt = 0.002\njoint_limits = false\n[controller]\nkind = \"joint_pd\"\nkp = 60\nkd = [20, 20, 20, 4, 4, 4]\n", step, 1500, x0, ref, x);
    for (int i = 0; i < 6; i++) {
        e0 = fmax(e0, fabs(ref[i] - x0[7 + i]));
        e = fmax(e, fabs(ref[i] - x[7 + i]));
    }
    CHECK(e < 0.05 * e0, "joint PD error %g of %g", e, e0);
    CHECK(angle_between(x0 + 3, x + 3) > 1e-4, "the base did not react");
}

/* computed_torque with kp = w^2, kd = 2w on an exact model: every joint's error is
 * e0 (1 + w t) exp(-w t) (the decoupled critically damped loop, paper eqs. 112-115). */
static void test_computed_torque(void) {
    double x0[13], x[13], ref[6], step[6], w = 5.0, t = 0.5;
    char law[256];
    for (int i = 0; i < 6; i++) step[i] = 0.2 - 0.07 * i;
    snprintf(law, sizeof law, "dt = 0.001\njoint_limits = false\n[controller]\nkind = \"computed_torque\"\nkp = %.17g\nkd = %.17g\n", w * w, 2 * w);
    run_to_set_point(law, step, 500, x0, ref, x);
    double decay = (1 + w * t) * exp(-w * t);
    for (int i = 0; i < 6; i++) {
        double e0 = ref[i] - x0[7 + i], e = ref[i] - x[7 + i];
        CHECK(fabs(e - e0 * decay) < 1e-7 * fabs(e0), "joint %d: error %.12g, closed form %.12g", i, e, e0 * decay);
    }
}

/* resolved_motion_rate along a line: the end effector follows the line and ends at its goal. */
static void test_resolved_motion_rate(void) {
    SpacearmModel *m = preset("spatial6");
    double x0[13], u0[12] = {0}, x[13], u[12], p0[3], p[3], goal[3], delta[3] = {0.05, 0.05, -0.05};
    char opts[1024];
    OK(spacearm_model_initial_configuration(m, x0));
    line_options(opts, sizeof opts, m, x0, delta, "dt = 0.002\njoint_limits = false\n[controller]\nkind = \"resolved_motion_rate\"\ngain = 5.0\n", "reference",
                 p0, goal);
    /* Half way (quintic timing: half the distance at t = 0.5 s). */
    OK(run(m, opts, x0, u0, NULL, 250, x, u));
    ee_position(m, x, p);
    double mid[3] = {(p0[0] + goal[0]) / 2, (p0[1] + goal[1]) / 2, (p0[2] + goal[2]) / 2};
    CHECK(dist3(p, mid) < 2e-3, "half way: %g m from the line's midpoint", dist3(p, mid));
    OK(run(m, opts, x0, u0, NULL, 750, x, u));
    ee_position(m, x, p);
    CHECK(dist3(p, goal) < 1e-3 * dist3(p0, goal), "end: %g m from the goal (the line is %g m)", dist3(p, goal), dist3(p0, goal));
    spacearm_model_free(m);
}

/* attitude with reaction wheels (rotation-floating): the base turns to quat_ref. */
static void test_attitude(void) {
    SpacearmModel *m = wheels_model();
    if (!m) return;
    size_t nx = spacearm_model_nx(m), nu = spacearm_model_nu(m);
    double x0[MAXN + 7], u0[MAXN + 6] = {0}, x[MAXN + 7], u[MAXN + 6];
    double ref[4] = {0.0, 0.0, sin(0.05), cos(0.05)};
    char q[256], opts[1024];
    CHECK(nx <= MAXN + 7 && nu <= MAXN + 6, "model size");
    OK(spacearm_model_initial_configuration(m, x0));
    list(q, ref, 4);
    snprintf(opts, sizeof opts, "mode = \"rotation-floating\"\ndt = 0.01\n[controller]\nkind = \"attitude\"\nquat_ref = %s\nkp = 10.0\nkd = 60.0\n", q);
    OK(run(m, opts, x0, u0, NULL, 2000, x, u));
    double a0 = angle_between(x0 + 3, ref), a = angle_between(x + 3, ref);
    CHECK(a < 0.05 * a0, "attitude error %g rad of %g", a, a0);
    /* The wheels (the last three dofs) turned the base: they turned themselves. */
    double turned = fabs(x[nx - 1] - x0[nx - 1]) + fabs(x[nx - 2] - x0[nx - 2]) + fabs(x[nx - 3] - x0[nx - 3]);
    CHECK(turned > 1.0, "the wheels turned %g rad in all", turned);
    spacearm_model_free(m);
}

/* base_thrusters (flying) holding the initial CM: with kp = 1, kd = 2 the CM obeys
 * c'' = -2 c' - (c - c0), so from a CM velocity v0 the momentum is P0 (1 - t) exp(-t). */
static void test_base_thrusters(void) {
    SpacearmModel *m = preset("spatial6");
    double x0[13], u0[12] = {0.2, -0.1, 0.05, 0, 0, 0, 0, 0, 0, 0, 0, 0}, x[13], u[12], mom0[9], mom[9], t = 1.0;
    OK(spacearm_model_initial_configuration(m, x0));
    OK(spacearm_momentum(m, x0, u0, mom0));
    OK(run(m, "mode = \"flying\"\ndt = 0.002\njoint_limits = false\n[controller]\nkind = \"base_thrusters\"\nkp_position = 1.0\nkd_position = 2.0\n", x0, u0,
           NULL, 500, x, u));
    OK(spacearm_momentum(m, x, u, mom));
    double want = (1 - t) * exp(-t);
    for (int i = 0; i < 3; i++) CHECK(fabs(mom[i] - mom0[i] * want) < 1e-9 * norm3(mom0), "P[%d] = %.12g, closed form %.12g", i, mom[i], mom0[i] * want);
    CHECK(norm3(mom0) > 1.0, "no initial momentum");
    spacearm_model_free(m);
}

/* coordinated_flying: the end effector follows its line while the base holds its pose. */
static void test_coordinated_flying(void) {
    SpacearmModel *m = preset("spatial6");
    double x0[13], u0[12] = {0}, x[13], u[12], p0[3], p[3], goal[3], delta[3] = {-0.1, 0.05, 0.05};
    char opts[1024];
    OK(spacearm_model_initial_configuration(m, x0));
    line_options(opts, sizeof opts, m, x0, delta, "mode = \"flying\"\ndt = 0.002\njoint_limits = false\n[controller]\nkind = \"coordinated_flying\"\n",
                 "ee_reference", p0, goal);
    OK(run(m, opts, x0, u0, NULL, 1500, x, u));
    ee_position(m, x, p);
    CHECK(dist3(p, goal) < 0.02 * dist3(p0, goal), "end effector %g m from the goal", dist3(p, goal));
    CHECK(dist3(x, x0) < 0.02 * dist3(p0, goal), "base moved %g m", dist3(x, x0));
    CHECK(angle_between(x + 3, x0 + 3) < 1e-2, "base turned %g rad", angle_between(x + 3, x0 + 3));
    spacearm_model_free(m);
}

/* momentum_damping (flying): F = -P / tau, and the torque about the CM -L_cm / tau, so both
 * decay as exp(-t / tau). */
static void test_momentum_damping(void) {
    SpacearmModel *m = preset("spatial6");
    double x0[13], u0[12] = {0.1, 0.05, -0.02, 0.01, -0.02, 0.03, 0.2, -0.1, 0.1, 0, 0.1, 0}, x[13], u[12], mom0[9], mom[9];
    double tau_s = 0.5, t = 1.0;
    OK(spacearm_model_initial_configuration(m, x0));
    OK(spacearm_momentum(m, x0, u0, mom0));
    OK(run(m, "mode = \"flying\"\ndt = 0.001\njoint_limits = false\n[controller]\nkind = \"momentum_damping\"\ntime_constant = 0.5\n", x0, u0, NULL, 1000, x,
           u));
    OK(spacearm_momentum(m, x, u, mom));
    double decay = exp(-t / tau_s);
    for (int i = 0; i < 3; i++) {
        CHECK(fabs(mom[i] - mom0[i] * decay) < 1e-9 * norm3(mom0), "P[%d] = %.12g, closed form %.12g", i, mom[i], mom0[i] * decay);
        CHECK(fabs(mom[6 + i] - mom0[6 + i] * decay) < 1e-9 * norm3(mom0 + 6), "L_cm[%d] = %.12g, closed form %.12g", i, mom[6 + i], mom0[6 + i] * decay);
    }
    CHECK(norm3(mom0) > 1.0 && norm3(mom0 + 6) > 0.1, "no initial momentum");
    spacearm_model_free(m);
}

/* combined: a joint PD on the arm and the attitude law on the wheels, both converging. */
static void test_combined(void) {
    SpacearmModel *m = wheels_model();
    if (!m) return;
    double x0[MAXN + 7], u0[MAXN + 6] = {0}, x[MAXN + 7], u[MAXN + 6], ref[6];
    double quat[4] = {0.0, sin(0.05), 0.0, cos(0.05)};
    char r[512], q[256], opts[2048];
    OK(spacearm_model_initial_configuration(m, x0));
    for (int i = 0; i < 6; i++) ref[i] = x0[7 + i] + 0.1;
    list(r, ref, 6);
    list(q, quat, 4);
    snprintf(opts, sizeof opts,
             "mode = \"rotation-floating\"\ndt = 0.002\n[controller]\nkind = \"combined\"\n"
             "arm = { kind = \"joint_pd\", kp = 60.0, kd = [20.0, 20.0, 20.0, 4.0, 4.0, 4.0], reference = %s }\n"
             "base = { kind = \"attitude\", quat_ref = %s, kp = 20.0, kd = 80.0 }\n",
             r, q);
    OK(run(m, opts, x0, u0, NULL, 10000, x, u));
    double e = 0.0;
    for (int i = 0; i < 6; i++) e = fmax(e, fabs(ref[i] - x[7 + i]));
    CHECK(e < 0.005, "arm error %g rad of 0.1", e);
    double a0 = angle_between(x0 + 3, quat), a = angle_between(x + 3, quat);
    CHECK(a < 0.05 * a0, "attitude error %g rad of %g", a, a0);
    spacearm_model_free(m);
}

/* torque_limit: a stiff joint PD far from its set point, clamped to 0.3 N m, is the constant
 * torque 0.3 N m on every joint while the errors stay positive (the same numbers, bit for bit). */
static void test_torque_limit(void) {
    SpacearmModel *m = preset("spatial6");
    double x0[13], u0[12] = {0}, x[13], u[12], x2[13], u2[12], ref[6], tau[6];
    char r[512], opts[1024];
    OK(spacearm_model_initial_configuration(m, x0));
    for (int i = 0; i < 6; i++) {
        ref[i] = x0[7 + i] + 0.5;
        tau[i] = 0.3;
    }
    list(r, ref, 6);
    snprintf(opts, sizeof opts,
             "dt = 0.002\njoint_limits = false\n[controller]\nkind = \"torque_limit\"\nlimit = 0.3\n"
             "controller = { kind = \"joint_pd\", kp = 1000.0, kd = 1.0, reference = %s }\n",
             r);
    OK(run(m, opts, x0, u0, NULL, 50, x, u));
    OK(run(m, "dt = 0.002\njoint_limits = false\n", x0, u0, tau, 50, x2, u2));
    CHECK(memcmp(x, x2, sizeof x) == 0 && memcmp(u, u2, sizeof u) == 0, "the clamped law is not the constant limit torque");
    CHECK(fabs(u[6]) > 1e-4, "nothing moved");
    spacearm_model_free(m);
}

/* Errors: the status and a message naming what was wrong. */
static void test_errors(void) {
    SpacearmModel *m = preset("spatial6");
    SpacearmStepper *s = NULL;
    struct {
        const char *options;
        SpacearmStatus status;
        const char *named;
    } cases[] = {
        {"[controller]\nkind = \"pid\"\n", SPACEARM_STATUS_PARSE, "pid"},
        {"[controller]\nkind = \"joint_pd\"\nkp = 1.0\nkd = 1.0\nreference = [0, 0, 0, 0, 0, 0]\nkpp = 3.0\n", SPACEARM_STATUS_PARSE, "kpp"},
        {"[controller]\nkind = \"joint_pd\"\nkp = 1.0\nkd = 1.0\nq_ref = [0, 0, 0, 0, 0, 0]\n", SPACEARM_STATUS_PARSE, "q_ref"},
        {"[controller]\nkind = \"joint_pd\"\nkp = \"high\"\nkd = 1.0\nreference = [0, 0, 0, 0, 0, 0]\n", SPACEARM_STATUS_PARSE, "number"},
        {"[controller]\nkind = \"joint_pd\"\nkp = -1.0\nkd = 1.0\nreference = [0, 0, 0, 0, 0, 0]\n", SPACEARM_STATUS_INVALID_ARGUMENT, "kp"},
        {"[controller]\nkind = \"joint_pd\"\nkp = 1.0\nkd = 1.0\nreference = [0, 0, 0]\n", SPACEARM_STATUS_DIMENSION, "reference"},
        {"mode = \"rotation-flying\"\n[controller]\nkind = \"attitude\"\nquat_ref = [0, 0, 0, 2]\nkp = 1\nkd = 1\n", SPACEARM_STATUS_NOT_UNIT_QUATERNION, "quat_ref"},
        {"mode = \"flying\"\n[controller]\nkind = \"momentum_damping\"\ntime_constant = 0.0\n", SPACEARM_STATUS_INVALID_ARGUMENT, "time_constant"},
        {"[controller]\nkind = \"resolved_motion_rate\"\ngain = 1.0\npoint = \"elbow\"\n"
         "reference = { kind = \"line\", p_start = [0, 0, 0], p_goal = [1, 0, 0], t_start = 0.0, t_end = 1.0 }\n",
         SPACEARM_STATUS_NOT_FOUND, "elbow"},
        {"[controller]\nkind = \"external\"\nindex = 0\n", SPACEARM_STATUS_INVALID_ARGUMENT, "external"},
        {"mode = \"flying\"\nthrusters = { max_force = -1.0 }\n", SPACEARM_STATUS_INVALID_ARGUMENT, "force"},
        {"wheels = [42]\n", SPACEARM_STATUS_NOT_FOUND, "42"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        s = NULL;
        SpacearmStatus st = spacearm_stepper_new(m, cases[i].options, &s);
        CHECK(st == cases[i].status && s == NULL, "case %zu: %s (want %s): %s", i, spacearm_status_name(st), spacearm_status_name(cases[i].status),
              spacearm_last_error());
        CHECK(strstr(spacearm_last_error(), cases[i].named) != NULL, "case %zu: the message does not name '%s': %s", i, cases[i].named, spacearm_last_error());
        spacearm_stepper_free(s);
    }
    spacearm_model_free(m);
}

int main(void) {
    test_none();
    test_joint_pd();
    test_computed_torque();
    test_resolved_motion_rate();
    test_attitude();
    test_base_thrusters();
    test_coordinated_flying();
    test_momentum_damping();
    test_combined();
    test_torque_limit();
    test_errors();
    if (FAILED()) return 1;
    printf("spacearm C controller tests passed\n");
    return 0;
}
