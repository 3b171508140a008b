/* Tests of the spacearm C ABI from C (run by scripts/c-tests.sh, also under AddressSanitizer
 * and UBSan). The checks are independent of the library's own code paths where they can be:
 * H* is recomputed here from the blocks H0, H0m, Hm (H* = Hm - H0m^T H0^-1 H0m, paper eq. 45,
 * with a 6x6 solve written here), forward dynamics is inverted by inverse dynamics, the momentum
 * map gives a state of zero momentum, and every error path answers its status and a message. */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "spacearm.h"
#include "check.h"

static double max_abs_diff(const double *a, const double *b, size_t n) {
    double m = 0.0;
    for (size_t i = 0; i < n; i++) {
        double d = fabs(a[i] - b[i]);
        if (d > m) m = d;
    }
    return m;
}

/* Solve A X = B for X (A 6x6 row-major, B 6xn row-major, both overwritten) by Gaussian
 * elimination with partial pivoting. */
static void solve6(double *a, double *b, size_t n) {
    for (int k = 0; k < 6; k++) {
        int p = k;
        for (int i = k + 1; i < 6; i++)
            if (fabs(a[i * 6 + k]) > fabs(a[p * 6 + k])) p = i;
        for (int j = 0; j < 6; j++) { double t = a[k * 6 + j]; a[k * 6 + j] = a[p * 6 + j]; a[p * 6 + j] = t; }
        for (size_t j = 0; j < n; j++) { double t = b[k * n + j]; b[k * n + j] = b[p * n + j]; b[p * n + j] = t; }
        for (int i = k + 1; i < 6; i++) {
            double f = a[i * 6 + k] / a[k * 6 + k];
            for (int j = k; j < 6; j++) a[i * 6 + j] -= f * a[k * 6 + j];
            for (size_t j = 0; j < n; j++) b[i * n + j] -= f * b[k * n + j];
        }
    }
    for (int k = 5; k >= 0; k--) {
        for (size_t j = 0; j < n; j++) {
            double s = b[k * n + j];
            for (int i = k + 1; i < 6; i++) s -= a[k * 6 + i] * b[i * n + j];
            b[k * n + j] = s / a[k * 6 + k];
        }
    }
}

static void test_quantities(void) {
    SpacearmModel *m = NULL;
    OK(spacearm_model_preset("spatial6", &m));
    size_t n = spacearm_model_n_dof(m), nx = spacearm_model_nx(m), nu = spacearm_model_nu(m);
    CHECK(n == 6 && nx == 13 && nu == 12, "sizes %zu %zu %zu", n, nx, nu);
    double x[13], u[12], f[12], du[12], f_back[12];
    OK(spacearm_model_initial_configuration(m, x));
    /* A generic state: base rotated (unit quaternion), joints away from the initial pose. */
    double qx = 0.1, qy = -0.2, qz = 0.3, qw = sqrt(1.0 - 0.01 - 0.04 - 0.09);
    x[3] = qx; x[4] = qy; x[5] = qz; x[6] = qw;
    for (size_t i = 0; i < n; i++) x[7 + i] += 0.1 * (double)(i + 1);
    for (size_t i = 0; i < nu; i++) { u[i] = 0.05 * (double)i - 0.2; f[i] = 1.0 - 0.3 * (double)i; }

    /* H symmetric; H* from the blocks. */
    double h[144], h0[36], h0m[36], hm[36], hs[36];
    OK(spacearm_mass_matrix(m, x, h));
    double asym = 0.0;
    for (size_t i = 0; i < nu; i++)
        for (size_t j = 0; j < nu; j++) asym = fmax(asym, fabs(h[i * nu + j] - h[j * nu + i]));
    CHECK(asym < 1e-12, "H not symmetric: %g", asym);
    OK(spacearm_inertia_blocks(m, x, h0, h0m, hm));
    CHECK(max_abs_diff(h0, h, 6) < 1e-12 && fabs(h0m[1] - h[7]) < 1e-12, "blocks are not those of H");
    OK(spacearm_generalized_inertia(m, x, hs));
    double y[36];
    memcpy(y, h0m, sizeof y);
    solve6(h0, y, n); /* y = H0^-1 H0m */
    double ref[36];
    for (size_t i = 0; i < n; i++)
        for (size_t j = 0; j < n; j++) {
            double s = hm[i * n + j];
            for (int k = 0; k < 6; k++) s -= h0m[k * n + i] * y[k * n + j];
            ref[i * n + j] = s;
        }
    CHECK(max_abs_diff(hs, ref, 36) < 1e-9, "H* differs from Hm - H0m^T H0^-1 H0m by %g", max_abs_diff(hs, ref, 36));

    /* Forward dynamics inverted by inverse dynamics. */
    OK(spacearm_forward_dynamics(m, x, u, f, du));
    OK(spacearm_inverse_dynamics(m, x, u, du, f_back));
    CHECK(max_abs_diff(f, f_back, nu) < 1e-9, "ID(FD(f)) - f = %g", max_abs_diff(f, f_back, nu));

    /* Reduced dynamics without a base wrench = ABA with f = [0; tau]; with one = ABA with [w; tau]. */
    double tau[6], w[6] = {3, -2, 1, 0.5, -0.4, 0.2}, f0[12] = {0}, du_r[12];
    for (size_t i = 0; i < n; i++) { tau[i] = f[6 + i]; f0[6 + i] = tau[i]; }
    OK(spacearm_forward_dynamics(m, x, u, f0, du));
    OK(spacearm_reduced_forward_dynamics(m, x, u, tau, NULL, du_r));
    CHECK(max_abs_diff(du, du_r, nu) < 1e-9, "reduced FD (floating) vs ABA: %g", max_abs_diff(du, du_r, nu));
    memcpy(f0, w, sizeof w);
    OK(spacearm_forward_dynamics(m, x, u, f0, du));
    OK(spacearm_reduced_forward_dynamics(m, x, u, tau, w, du_r));
    CHECK(max_abs_diff(du, du_r, nu) < 1e-9, "reduced FD (base wrench) vs ABA: %g", max_abs_diff(du, du_r, nu));

    /* c = ID at zero acceleration; c* and J* of the end effector are finite and have their sizes. */
    double c[12], zero[12] = {0}, cs[6], js[36], off[3];
    size_t body = 99;
    OK(spacearm_bias_forces(m, x, u, c));
    OK(spacearm_inverse_dynamics(m, x, u, zero, f_back));
    CHECK(max_abs_diff(c, f_back, nu) < 1e-12, "c vs ID(u_dot = 0): %g", max_abs_diff(c, f_back, nu));
    OK(spacearm_generalized_bias(m, x, u, cs));
    OK(spacearm_model_point(m, NULL, &body, off));
    CHECK(body == n, "end effector on body %zu", body);
    OK(spacearm_generalized_jacobian(m, x, body, off, js));

    /* The momentum map: the base velocity it gives makes the momentum zero. */
    double qd[6], p0[3] = {0}, v0[6], mom[9], uu[12];
    for (size_t i = 0; i < n; i++) qd[i] = u[6 + i];
    OK(spacearm_base_velocity_from_momentum(m, x, qd, p0, p0, v0));
    memcpy(uu, v0, sizeof v0);
    memcpy(uu + 6, qd, sizeof qd);
    OK(spacearm_momentum(m, x, uu, mom));
    CHECK(max_abs_diff(mom, zero, 6) < 1e-9, "momentum after the momentum map: %g", max_abs_diff(mom, zero, 6));

    /* Derivatives: d(u_dot)/df = H^-1, so H (d u_dot/df) = I. */
    double hinv[144];
    OK(spacearm_forward_dynamics_derivatives(m, x, u, f, NULL, NULL, hinv));
    double worst = 0.0;
    for (size_t i = 0; i < nu; i++)
        for (size_t j = 0; j < nu; j++) {
            double s = 0.0;
            for (size_t k = 0; k < nu; k++) s += h[i * nu + k] * hinv[k * nu + j];
            worst = fmax(worst, fabs(s - (i == j ? 1.0 : 0.0)));
        }
    CHECK(worst < 1e-9, "H * dFD/df - I = %g", worst);

    /* The TOML round trip gives the same model. */
    size_t needed = 0;
    CHECK(spacearm_model_to_toml(m, NULL, 0, &needed) == SPACEARM_STATUS_BUFFER_TOO_SMALL && needed > 10, "needed %zu", needed);
    char *text = malloc(needed);
    OK(spacearm_model_to_toml(m, text, needed, &needed));
    SpacearmModel *again = NULL;
    OK(spacearm_model_from_toml(text, &again));
    double h2[144];
    OK(spacearm_mass_matrix(again, x, h2));
    CHECK(max_abs_diff(h, h2, 144) == 0.0, "round trip changed H by %g", max_abs_diff(h, h2, 144));
    free(text);
    spacearm_model_free(again);
    spacearm_model_free(m);
}

static void test_errors(void) {
    SpacearmModel *m = NULL;
    CHECK(spacearm_model_from_toml("[base\nmass = 1", &m) == SPACEARM_STATUS_PARSE && m == NULL, "bad TOML");
    CHECK(strlen(spacearm_last_error()) > 0, "no message for bad TOML");
    CHECK(spacearm_model_preset("nope", &m) == SPACEARM_STATUS_NOT_FOUND, "unknown preset");
    CHECK(strstr(spacearm_last_error(), "nope") != NULL, "message: %s", spacearm_last_error());
    CHECK(spacearm_model_preset(NULL, &m) == SPACEARM_STATUS_NULL_POINTER, "NULL name");
    CHECK(spacearm_model_from_toml_file("/nonexistent/model.toml", &m) == SPACEARM_STATUS_IO, "missing file");
    OK(spacearm_model_preset("planar4", &m));
    CHECK(strlen(spacearm_last_error()) == 0, "a success leaves a message: %s", spacearm_last_error());
    double x[11] = {0, 0, 0, 0, 0, 0, 2.0, 0, 0, 0, 0}, h[100];
    CHECK(spacearm_mass_matrix(m, x, h) == SPACEARM_STATUS_NOT_UNIT_QUATERNION, "quaternion");
    x[6] = NAN;
    CHECK(spacearm_mass_matrix(m, x, h) == SPACEARM_STATUS_NON_FINITE, "NaN: %s", spacearm_last_error());
    x[6] = 1.0;
    CHECK(spacearm_mass_matrix(m, x, NULL) == SPACEARM_STATUS_NULL_POINTER, "NULL output");
    CHECK(spacearm_mass_matrix(NULL, x, h) == SPACEARM_STATUS_NULL_POINTER, "NULL model");
    CHECK(spacearm_model_n_dof(NULL) == 0, "n_dof of NULL");
    double off[3] = {0};
    size_t body;
    CHECK(spacearm_generalized_jacobian(m, x, 42, off, h) == SPACEARM_STATUS_NOT_FOUND, "body 42: %s", spacearm_last_error());
    CHECK(spacearm_model_point(m, "no such point", &body, off) == SPACEARM_STATUS_NOT_FOUND, "point");
    SpacearmStepper *s = NULL;
    /* An unknown name in the run description (a mode, like a controller kind) is the reader's: PARSE, with the line. */
    CHECK(spacearm_stepper_new(m, "mode = \"hovering\"", &s) == SPACEARM_STATUS_PARSE, "mode: %s", spacearm_last_error());
    CHECK(strstr(spacearm_last_error(), "rotation-floating") != NULL, "mode names: %s", spacearm_last_error());
    CHECK(spacearm_stepper_new(m, "dt = -1", &s) == SPACEARM_STATUS_INVALID_ARGUMENT, "dt");
    CHECK(spacearm_stepper_new(m, "speed = 3", &s) == SPACEARM_STATUS_PARSE, "unknown option");
    OK(spacearm_stepper_new(m, NULL, &s));
    CHECK(spacearm_stepper_step(s, NULL, NULL, 1) == SPACEARM_STATUS_INVALID_ARGUMENT, "step before reset");
    CHECK(isnan(spacearm_stepper_time(s)), "time before reset");
    spacearm_stepper_free(s);
    spacearm_model_free(m);
    spacearm_model_free(NULL);
    spacearm_stepper_free(NULL);
}

static void test_stepper(void) {
    SpacearmModel *m = NULL;
    OK(spacearm_model_preset("spatial6", &m));
    SpacearmStepper *s = NULL;
    OK(spacearm_stepper_new(m, "mode = \"floating\"\ndt = 0.001\n", &s));
    double x0[13], u0[12] = {0}, tau[6] = {1, -1, 0.5, 0.2, -0.1, 0.1}, x[13], u[12], mom[9];
    OK(spacearm_model_initial_configuration(m, x0));
    spacearm_model_free(m); /* the stepper keeps its own copy */
    OK(spacearm_stepper_reset(s, x0, u0));
    OK(spacearm_stepper_step(s, tau, NULL, 200));
    CHECK(fabs(spacearm_stepper_time(s) - 0.2) < 1e-12, "time %g", spacearm_stepper_time(s));
    OK(spacearm_stepper_state(s, x, u));
    CHECK(fabs(u[6] - u0[6]) > 1e-3, "the joints did not move");
    /* Joint torques are internal: the momentum stays zero (with the model's own momentum). */
    OK(spacearm_model_preset("spatial6", &m));
    OK(spacearm_momentum(m, x, u, mom));
    CHECK(fabs(mom[0]) + fabs(mom[1]) + fabs(mom[2]) + fabs(mom[3]) + fabs(mom[4]) + fabs(mom[5]) < 1e-9, "momentum drifted");
    /* Reset gives the same run again, bit for bit. */
    double x2[13];
    OK(spacearm_stepper_reset(s, x0, u0));
    OK(spacearm_stepper_step(s, tau, NULL, 200));
    OK(spacearm_stepper_state(s, x2, NULL));
    CHECK(max_abs_diff(x, x2, 13) == 0.0, "reset did not repeat the run");
    double bad[6] = {NAN, 0, 0, 0, 0, 0};
    CHECK(spacearm_stepper_step(s, bad, NULL, 1) == SPACEARM_STATUS_NON_FINITE, "NaN torque");
    spacearm_stepper_free(s);
    spacearm_model_free(m);
}

/* Issue 38: every status has a name, and any other int gives a fixed string (no read out of
 * bounds: the sanitized run would catch one). */
static void test_status_names(void) {
    for (int32_t s = 0; s <= SPACEARM_STATUS_INTERNAL; s++) {
        const char *name = spacearm_status_name(s);
        CHECK(name != NULL && strlen(name) > 0 && strcmp(name, "unknown status") != 0, "status %d has no name", (int)s);
        for (int32_t t = 0; t < s; t++) CHECK(strcmp(name, spacearm_status_name(t)) != 0, "statuses %d and %d share a name", (int)s, (int)t);
    }
    const int32_t outside[] = {-1, SPACEARM_STATUS_INTERNAL + 1, 1000, INT32_MIN, INT32_MAX};
    for (size_t i = 0; i < sizeof outside / sizeof outside[0]; i++)
        CHECK(strcmp(spacearm_status_name(outside[i]), "unknown status") == 0, "status %d: %s", (int)outside[i], spacearm_status_name(outside[i]));
}

/* Issue 38: a result that would be non-finite from finite inputs is NON_FINITE with a message,
 * and its buffer is left as it was; a non-finite input (an offset, a base wrench, P, L) is
 * refused as NON_FINITE. */
static void test_non_finite(void) {
    SpacearmModel *m = NULL;
    OK(spacearm_model_preset("spatial6", &m));
    double x[13], u[12] = {0}, f[12] = {0}, out[144], off[3] = {0, 0, 0}, w[6] = {0}, p[3] = {0}, l[3] = {0}, qd[6] = {0};
    OK(spacearm_model_initial_configuration(m, x));
    /* UNWRITTEN(n): the first and n-th values of `out` are still the 7.0 that FRESH() put there. */
#define FRESH() for (size_t k_ = 0; k_ < 144; k_++) out[k_] = 7.0
#define UNWRITTEN(n) (out[0] == 7.0 && out[(n) - 1] == 7.0)
    for (int sign = -1; sign <= 1; sign += 2) {
        for (size_t i = 0; i < 12; i++) u[i] = sign * 1e300;
        FRESH();
        CHECK(spacearm_forward_dynamics(m, x, u, f, out) == SPACEARM_STATUS_NON_FINITE && UNWRITTEN(12), "FD at u = %g", u[0]);
        CHECK(strstr(spacearm_last_error(), "non-finite") != NULL, "message: %s", spacearm_last_error());
        FRESH();
        CHECK(spacearm_bias_forces(m, x, u, out) == SPACEARM_STATUS_NON_FINITE && UNWRITTEN(12), "c at u = %g", u[0]);
        FRESH();
        CHECK(spacearm_generalized_bias(m, x, u, out) == SPACEARM_STATUS_NON_FINITE && UNWRITTEN(6), "c* at u = %g", u[0]);
        FRESH();
        CHECK(spacearm_inverse_dynamics(m, x, u, f, out) == SPACEARM_STATUS_NON_FINITE && UNWRITTEN(12), "ID at u = %g", u[0]);
        FRESH();
        FRESH();
        CHECK(spacearm_forward_dynamics_derivatives(m, x, u, f, out, NULL, NULL) == SPACEARM_STATUS_NON_FINITE && UNWRITTEN(144), "derivatives at u = %g", u[0]);
    }
    for (size_t i = 0; i < 12; i++) { u[i] = 0.0; f[i] = DBL_MAX; }
    FRESH();
    CHECK(spacearm_forward_dynamics(m, x, u, f, out) == SPACEARM_STATUS_NON_FINITE && UNWRITTEN(12), "FD at f = DBL_MAX");
    FRESH();
    CHECK(spacearm_inverse_dynamics(m, x, u, f, out) == SPACEARM_STATUS_NON_FINITE && UNWRITTEN(12), "ID at du = DBL_MAX");
    for (size_t i = 0; i < 6; i++) w[i] = DBL_MAX;
    FRESH();
    CHECK(spacearm_reduced_forward_dynamics(m, x, u, f, w, out) == SPACEARM_STATUS_NON_FINITE && UNWRITTEN(12), "reduced FD at DBL_MAX");
    /* Non-finite inputs of every kind. */
    size_t body = 6;
    off[1] = NAN;
    FRESH();
    CHECK(spacearm_generalized_jacobian(m, x, body, off, out) == SPACEARM_STATUS_NON_FINITE && UNWRITTEN(36), "NaN offset: %s", spacearm_last_error());
    CHECK(strstr(spacearm_last_error(), "offset") != NULL, "message: %s", spacearm_last_error());
    FRESH();
    CHECK(spacearm_point_pose(m, x, body, off, out, NULL) == SPACEARM_STATUS_NON_FINITE && UNWRITTEN(3), "NaN offset (pose)");
    w[3] = INFINITY;
    for (size_t i = 0; i < 12; i++) f[i] = 0.0;
    CHECK(spacearm_reduced_forward_dynamics(m, x, u, f, w, out) == SPACEARM_STATUS_NON_FINITE && strstr(spacearm_last_error(), "base_wrench"), "inf base wrench: %s", spacearm_last_error());
    p[0] = NAN;
    CHECK(spacearm_base_velocity_from_momentum(m, x, qd, p, l, out) == SPACEARM_STATUS_NON_FINITE, "NaN p");
    qd[2] = NAN;
    CHECK(spacearm_base_velocity_from_momentum(m, x, qd, l, l, out) == SPACEARM_STATUS_NON_FINITE, "NaN qd");
#undef UNWRITTEN
#undef FRESH
    /* A large but representable state still answers OK with finite values. */
    for (size_t i = 0; i < 12; i++) u[i] = 1e3;
    OK(spacearm_forward_dynamics(m, x, u, f, out));
    for (size_t i = 0; i < 12; i++) CHECK(isfinite(out[i]), "FD entry %zu = %g", i, out[i]);
    spacearm_model_free(m);
}

/* Issue 38: a TOML text that is not TOML is PARSE; TOML that breaks a model rule is
 * INVALID_MODEL (as docs/c-api.md says), with the line in the message. */
static void test_model_rules(void) {
    SpacearmModel *m = NULL;
    const char *negative_mass = "[model]\nname = \"neg\"\n[base]\nmass = -100.0\ninertia = [10.0, 10.0, 10.0]\n";
    CHECK(spacearm_model_from_toml(negative_mass, &m) == SPACEARM_STATUS_INVALID_MODEL && m == NULL, "negative mass: %s", spacearm_last_error());
    CHECK(strstr(spacearm_last_error(), ":4:") != NULL, "no line in: %s", spacearm_last_error());
    const char *unknown_key = "[model]\nname = \"k\"\n[base]\nmass = 100.0\ninertia = [10.0, 10.0, 10.0]\ncolour = 3\n";
    CHECK(spacearm_model_from_toml(unknown_key, &m) == SPACEARM_STATUS_INVALID_MODEL && m == NULL, "unknown key: %s", spacearm_last_error());
    CHECK(spacearm_model_from_toml("[model\nname = 1", &m) == SPACEARM_STATUS_PARSE && m == NULL, "syntax: %s", spacearm_last_error());
    OK(spacearm_model_from_toml("[model]\nname = \"ok\"\n[base]\nmass = 100.0\ninertia = [10.0, 10.0, 10.0]\n", &m));
    spacearm_model_free(m);
}

/* Issue 38: a success clears the message of an earlier failure, in the calls that return a
 * status and in those that return a value. */
static void test_success_clears_the_message(void) {
    SpacearmModel *m = NULL;
    OK(spacearm_model_preset("planar4", &m));
    CHECK(spacearm_model_preset("nope", NULL) != SPACEARM_STATUS_OK && strlen(spacearm_last_error()) > 0, "a failure");
    CHECK(spacearm_model_nx(m) == 11, "nx");
    CHECK(strlen(spacearm_last_error()) == 0, "spacearm_model_nx left: %s", spacearm_last_error());
    CHECK(spacearm_model_n_dof(NULL) == 0 && strlen(spacearm_last_error()) > 0, "n_dof(NULL) has a message");
    CHECK(spacearm_model_total_mass(m) > 0.0 && strlen(spacearm_last_error()) == 0, "total_mass left: %s", spacearm_last_error());
    CHECK(spacearm_model_nu(NULL) == 0, "nu(NULL)");
    double x[11];
    OK(spacearm_model_initial_configuration(m, x));
    CHECK(strlen(spacearm_last_error()) == 0, "a status call left: %s", spacearm_last_error());
    spacearm_model_free(m);
}

/* Issue 38: the derivatives with every output NULL are a valid call (the header allows each
 * output to be NULL) that still checks its inputs. */
static void test_derivatives_null_outputs(void) {
    SpacearmModel *m = NULL;
    OK(spacearm_model_preset("spatial6", &m));
    double x[13], u[12] = {0}, f[12] = {0};
    OK(spacearm_model_initial_configuration(m, x));
    OK(spacearm_forward_dynamics_derivatives(m, x, u, f, NULL, NULL, NULL));
    x[6] = 2.0;
    CHECK(spacearm_forward_dynamics_derivatives(m, x, u, f, NULL, NULL, NULL) == SPACEARM_STATUS_NOT_UNIT_QUATERNION, "inputs not checked");
    spacearm_model_free(m);
}

/* Issue 38: no stepper call runs unbounded: dt within [SPACEARM_MIN_DT, SPACEARM_MAX_DT], at
 * most SPACEARM_MAX_STEPS_PER_CALL steps per call, refused before any step. */
static void test_stepper_bounds(void) {
    SpacearmModel *m = NULL;
    OK(spacearm_model_preset("planar4", &m));
    SpacearmStepper *s = NULL;
    const char *bad_dt[] = {"dt = 1e-300", "dt = 1e300", "dt = 1e-7", "dt = 11.0", "dt = nan", "dt = inf", "dt = 0.0"};
    for (size_t i = 0; i < sizeof bad_dt / sizeof bad_dt[0]; i++) {
        CHECK(spacearm_stepper_new(m, bad_dt[i], &s) == SPACEARM_STATUS_INVALID_ARGUMENT && s == NULL, "%s: %s", bad_dt[i], spacearm_last_error());
        CHECK(strstr(spacearm_last_error(), "dt") != NULL, "message: %s", spacearm_last_error());
    }
    OK(spacearm_stepper_new(m, "dt = 1e-6", &s));
    spacearm_stepper_free(s);
    OK(spacearm_stepper_new(m, "dt = 10.0", &s));
    spacearm_stepper_free(s);
    OK(spacearm_stepper_new(m, "dt = 0.001", &s));
    double x0[11], u0[10] = {0};
    OK(spacearm_model_initial_configuration(m, x0));
    OK(spacearm_stepper_reset(s, x0, u0));
    const size_t too_many[] = {SIZE_MAX, (size_t)SPACEARM_MAX_STEPS_PER_CALL + 1};
    for (size_t i = 0; i < 2; i++) {
        CHECK(spacearm_stepper_step(s, NULL, NULL, too_many[i]) == SPACEARM_STATUS_INVALID_ARGUMENT, "%zu steps", too_many[i]);
        CHECK(strstr(spacearm_last_error(), "SPACEARM_MAX_STEPS_PER_CALL") != NULL, "message: %s", spacearm_last_error());
        CHECK(spacearm_stepper_time(s) == 0.0, "steps were taken before the refusal: t = %g", spacearm_stepper_time(s));
    }
    OK(spacearm_stepper_step(s, NULL, NULL, 10));
    CHECK(fabs(spacearm_stepper_time(s) - 0.01) < 1e-15, "t = %g", spacearm_stepper_time(s));
    spacearm_stepper_free(s);
    spacearm_model_free(m);
}

/* Model editing (the core's model/edit.rs): a payload attached to a bare base has the composite
 * mass properties of the parallel-axis theorem, computed here (the base block of H at the
 * identity pose is the kinetic energy's Hessian of base + payload: M E, -m [p]x — the CM — and
 * I0 + R Ip R^T + m (|p|^2 E - p p^T)); a payload on spatial6 gives the H of the same model
 * written as TOML with the payload a fixed link (the builder's path, as Python's); a whole model
 * attached and removed again gives the host's H back bit for bit; bad edits answer a status. */
static void test_model_editing(void) {
    SpacearmModel *bus = NULL, *sat = NULL;
    OK(spacearm_model_from_toml("[model]\nname = \"sat\"\n[base]\nname = \"bus\"\nmass = 300.0\ninertia = [40.0, 55.0, 61.0]\n", &bus));
    const double m0 = 300.0, m = 25.0, p[3] = {0.8, -0.3, 1.2}, ip[3] = {2.0, 3.0, 4.0};
    const double qz = sin(0.2), qw = cos(0.2), rot[4] = {0.0, 0.0, qz, qw};
    const double inertia[9] = {ip[0], 0, 0, 0, ip[1], 0, 0, 0, ip[2]};
    OK(spacearm_model_attach_body(bus, "tank", "bus", p, rot, m, inertia, &sat));
    CHECK(spacearm_model_n_dof(sat) == 0 && spacearm_model_n_bodies(sat) == 2, "attached: %zu dof, %zu bodies", spacearm_model_n_dof(sat), spacearm_model_n_bodies(sat));
    CHECK(spacearm_model_total_mass(sat) == m0 + m, "total mass %.17g", spacearm_model_total_mass(sat));
    CHECK(spacearm_model_n_bodies(bus) == 1, "the input model changed");
    double x[7] = {0, 0, 0, 0, 0, 0, 1}, h[36];
    OK(spacearm_mass_matrix(sat, x, h));
    /* R = Rz(0.4); R Ip R^T; the parallel-axis term. */
    double c = cos(0.4), s = sin(0.4), r[9] = {c, -s, 0, s, c, 0, 0, 0, 1}, expect[36] = {0};
    double p2 = p[0] * p[0] + p[1] * p[1] + p[2] * p[2], i0[3] = {40.0, 55.0, 61.0};
    for (int i = 0; i < 3; i++) {
        expect[i * 6 + i] = m0 + m;
        for (int j = 0; j < 3; j++) {
            double rir = 0.0;
            for (int k = 0; k < 3; k++) rir += r[i * 3 + k] * ip[k] * r[j * 3 + k];
            expect[(3 + i) * 6 + 3 + j] = (i == j ? i0[i] + m * p2 : 0.0) + rir - m * p[i] * p[j];
        }
    }
    /* -m [p]x: the coupling of v0 and w0 (the CM offset m p / M times M). */
    double px[9] = {0, -p[2], p[1], p[2], 0, -p[0], -p[1], p[0], 0};
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) { expect[i * 6 + 3 + j] = -m * px[i * 3 + j]; expect[(3 + i) * 6 + j] = -m * px[j * 3 + i]; }
    CHECK(max_abs_diff(h, expect, 36) < 1e-12, "H of base + payload vs the parallel-axis theorem: %g", max_abs_diff(h, expect, 36));

    /* A payload on spatial6's link6 against the same model written as TOML. */
    SpacearmModel *arm = NULL, *held = NULL, *by_text = NULL;
    OK(spacearm_model_preset("spatial6", &arm));
    OK(spacearm_model_attach_body(arm, "payload", "link6", p, rot, m, inertia, &held));
    size_t needed = 0;
    spacearm_model_to_toml(arm, NULL, 0, &needed);
    char *text = malloc(needed + 512);
    OK(spacearm_model_to_toml(arm, text, needed, NULL));
    snprintf(text + strlen(text), 512,
             "\n[[link]]\nname = \"payload\"\nparent = \"link6\"\ncom = [0.0, 0.0, 0.0]\nmass = %.17g\ninertia = [%.17g, %.17g, %.17g]\n"
             "joint = { name = \"payload_joint\", type = \"fixed\", origin = [%.17g, %.17g, %.17g], rotation = [0.0, 0.0, %.17g, %.17g] }\n",
             m, ip[0], ip[1], ip[2], p[0], p[1], p[2], qz, qw);
    OK(spacearm_model_from_toml(text, &by_text));
    free(text);
    double xa[13], ha[144], hb[144];
    OK(spacearm_model_initial_configuration(arm, xa));
    for (size_t i = 0; i < 6; i++) xa[7 + i] += 0.2 * (double)i - 0.5;
    OK(spacearm_mass_matrix(held, xa, ha));
    OK(spacearm_mass_matrix(by_text, xa, hb));
    CHECK(max_abs_diff(ha, hb, 144) == 0.0, "attached vs TOML-built payload: H differs by %g", max_abs_diff(ha, hb, 144));
    CHECK(spacearm_model_total_mass(held) == spacearm_model_total_mass(arm) + m, "total mass with the payload");

    /* A whole model attached, then removed: the host back, bit for bit. */
    SpacearmModel *planar = NULL, *both = NULL, *back = NULL;
    OK(spacearm_model_preset("planar4", &planar));
    const double at[3] = {1.5, 0.0, 0.0};
    OK(spacearm_model_attach_model(arm, planar, "base", at, NULL, "p4_", "mount", &both));
    CHECK(spacearm_model_n_dof(both) == 6 + spacearm_model_n_dof(planar), "attached model: N = %zu", spacearm_model_n_dof(both));
    CHECK(fabs(spacearm_model_total_mass(both) - spacearm_model_total_mass(arm) - spacearm_model_total_mass(planar)) < 1e-12, "attached model's mass");
    size_t body = 0;
    double off[3];
    OK(spacearm_model_point(both, "p4_end_effector", &body, off));
    CHECK(body == 7 + spacearm_model_n_bodies(planar) - 1, "the attached end-effector point is on body %zu", body);
    OK(spacearm_model_remove_subtree(both, "mount", &back));
    OK(spacearm_mass_matrix(back, xa, hb));
    OK(spacearm_mass_matrix(arm, xa, ha));
    CHECK(max_abs_diff(ha, hb, 144) == 0.0, "remove_subtree(attach_model) changed H by %g", max_abs_diff(ha, hb, 144));

    /* Refusals: a status and a message naming what was wrong. */
    SpacearmModel *none = NULL;
    CHECK(spacearm_model_remove_subtree(arm, "base", &none) == SPACEARM_STATUS_INVALID_MODEL && none == NULL, "removing the base");
    CHECK(strstr(spacearm_last_error(), "is the base") != NULL, "message: %s", spacearm_last_error());
    CHECK(spacearm_model_attach_body(arm, "p", "ghost", p, NULL, 1.0, NULL, &none) == SPACEARM_STATUS_INVALID_MODEL, "unknown parent");
    CHECK(strstr(spacearm_last_error(), "ghost") != NULL, "message: %s", spacearm_last_error());
    CHECK(spacearm_model_attach_body(arm, "p", "base", p, NULL, -1.0, NULL, &none) == SPACEARM_STATUS_INVALID_MODEL, "negative mass");
    CHECK(spacearm_model_attach_model(arm, arm, "base", at, NULL, "", "copy", &none) == SPACEARM_STATUS_INVALID_MODEL, "name clash");
    CHECK(strstr(spacearm_last_error(), "used twice") != NULL, "message: %s", spacearm_last_error());
    CHECK(spacearm_model_attach_model(arm, NULL, "base", at, NULL, "c_", NULL, &none) == SPACEARM_STATUS_NULL_POINTER, "NULL other");
    CHECK(spacearm_model_attach_body(arm, "p", "base", NULL, NULL, 1.0, NULL, &none) == SPACEARM_STATUS_NULL_POINTER, "NULL origin");
    CHECK(spacearm_model_attach_body(arm, "p", "base", p, NULL, 1.0, NULL, NULL) == SPACEARM_STATUS_NULL_POINTER, "NULL out");
    CHECK(none == NULL, "a refused edit wrote a handle");
    spacearm_model_free(bus); spacearm_model_free(sat); spacearm_model_free(arm); spacearm_model_free(held);
    spacearm_model_free(by_text); spacearm_model_free(planar); spacearm_model_free(both); spacearm_model_free(back);
}

int main(void) {
    CHECK(spacearm_abi_version() == SPACEARM_ABI_VERSION, "ABI %u vs header %u", spacearm_abi_version(), SPACEARM_ABI_VERSION);
    test_quantities();
    test_errors();
    test_stepper();
    test_status_names();
    test_non_finite();
    test_model_rules();
    test_success_clears_the_message();
    test_derivatives_null_outputs();
    test_stepper_bounds();
    test_model_editing();
    if (FAILED()) return 1;
    printf("spacearm C ABI tests passed (ABI %u, spacearm %s)\n", spacearm_abi_version(), spacearm_version());
    return 0;
}
