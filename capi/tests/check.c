/* The C API as a C renderer's test would use it (compiled and run by
 * scripts/check-c-api; also compiled as C++ there): the reference tracer's
 * values pass, values 10 % high fail, bad input gives its status and a
 * message naming the field. Exit 0 when every expectation holds. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#ifdef __cplusplus
#include <cstdlib>
#endif

#include "mcrt_noise.h"

static int failures = 0;

#define EXPECT(cond, what)                                                         \
    do {                                                                           \
        if (!(cond)) {                                                             \
            fprintf(stderr, "FAILED: %s (line %d): %s\n", what, __LINE__, #cond);  \
            failures++;                                                            \
        }                                                                          \
    } while (0)

/* A failure here makes the rest meaningless: say why, and stop. */
#define REQUIRE(call, what)                                                            \
    do {                                                                               \
        if ((call) != MCRT_STATUS_OK) {                                                \
            fprintf(stderr, "FAILED: %s (line %d): %s\n", what, __LINE__, mcrt_last_error()); \
            return 1;                                                                  \
        }                                                                              \
    } while (0)

enum { ITERATIONS = 200000 };

#ifdef __cplusplus
/* A renderer's registry torn down after main: a failing call during process
 * exit must return its status, not abort. */
static struct TornDownAfterMain {
    ~TornDownAfterMain() {
        McrtScene *scene = NULL;
        if (mcrt_scene_from_toml("not a scene", &scene) != MCRT_STATUS_INVALID_SCENE) std::abort();
    }
} torn_down_after_main;
#endif

static McrtVerdict *check_values(const McrtPrediction *prediction, const double *values, size_t n,
                                 const McrtCheckOptions *options) {
    McrtSamples *samples = mcrt_samples_new();
    McrtVerdict *verdict = NULL;
    /* In two chunks: the exact sums give the same verdict as one. */
    EXPECT(mcrt_samples_extend(samples, values, n / 3) == MCRT_STATUS_OK, "first chunk");
    EXPECT(mcrt_samples_extend(samples, values + n / 3, n - n / 3) == MCRT_STATUS_OK, "second chunk");
    EXPECT(mcrt_samples_count(samples) == n, "count");
    EXPECT(mcrt_check(prediction, samples, options, &verdict) == MCRT_STATUS_OK, "check runs");
    mcrt_samples_free(samples);
    return verdict;
}

int main(int argc, char **argv) {
    if (argc != 2) {
        fprintf(stderr, "usage: %s SCENE.toml\n", argv[0]);
        return 2;
    }
    McrtScene *scene = NULL;
    if (mcrt_scene_from_file(argv[1], &scene) != MCRT_STATUS_OK) {
        fprintf(stderr, "%s\n", mcrt_last_error());
        return 1;
    }
    McrtPrediction *prediction = NULL;
    REQUIRE(mcrt_predict(scene, &prediction), "predict");
    McrtPredicted mean = mcrt_prediction_mean(prediction);
    McrtPredicted var = mcrt_prediction_variance(prediction);
    printf("mean %.10e +- %.1e (quadrature) +- %.1e (model)\n", mean.value, mean.quadrature_bar, mean.model_bar);
    printf("Var L %.10e +- %.1e (quadrature) +- %.1e (model)\n", var.value, var.quadrature_bar, var.model_bar);
    EXPECT(mean.value > 0 && mean.quadrature_bar > 0 && mean.quadrature_bar < 1e-9 * mean.value, "mean with a bar");

    double *values = (double *)malloc(ITERATIONS * sizeof(double));
    REQUIRE(mcrt_reference_values(scene, 11, 0, ITERATIONS, values), "reference values");

    /* Correct values pass. */
    McrtVerdict *verdict = check_values(prediction, values, ITERATIONS, NULL);
    double z_mean = 0.0, z_var = 0.0;
    EXPECT(mcrt_verdict_status(verdict) == MCRT_VERDICT_STATUS_PASS, "correct values pass");
    EXPECT(mcrt_verdict_passed(verdict) == 1, "passed");
    EXPECT(mcrt_verdict_z_mean(verdict, &z_mean) == 1 && fabs(z_mean) < mcrt_verdict_z_limit(verdict), "z of the mean");
    EXPECT(mcrt_verdict_z_variance(verdict, &z_var) == 1 && fabs(z_var) < mcrt_verdict_z_limit(verdict), "z of Var L");
    EXPECT(strncmp(mcrt_verdict_text(verdict), "PASS: 200000 samples", 20) == 0, "the CLI's text");
    EXPECT(strstr(mcrt_verdict_json(verdict), "\"status\": \"pass\"") != NULL, "the CLI's JSON");
    printf("correct values: %s\n", mcrt_verdict_text(verdict));
    mcrt_verdict_free(verdict);

    /* Values 10 % high fail, by the mean's z-test. */
    for (size_t i = 0; i < ITERATIONS; i++) values[i] *= 1.1;
    verdict = check_values(prediction, values, ITERATIONS, NULL);
    EXPECT(mcrt_verdict_status(verdict) == MCRT_VERDICT_STATUS_FAIL, "values 10 % high fail");
    EXPECT(mcrt_verdict_z_mean(verdict, &z_mean) == 1 && z_mean > mcrt_verdict_z_limit(verdict), "beyond the limit");
    printf("values 10 %% high: z of the mean %+.2f\n", z_mean);
    mcrt_verdict_free(verdict);

    /* Too few values: not resolved. */
    verdict = check_values(prediction, values, 500, NULL);
    EXPECT(mcrt_verdict_status(verdict) == MCRT_VERDICT_STATUS_NOT_RESOLVED, "500 values do not resolve");
    mcrt_verdict_free(verdict);

    /* Bad input: a status and a message naming the field. */
    McrtScene *bad = NULL;
    const char *toml = "[medium]\nsigma_ext = 1.0\nalbedo = 0.8\n[[lights]]\nkind = \"point\"\nposition = [1.0, 0.0, 1.0]\n"
                       "flux = 1.0\n[camera]\norigin = [0.0, 0.0, 0.0]\ndirection = [0.0, 0.0, 1.0]\n"
                       "[estimator]\nradius = 0.2\nq = 1.5\nforward_rays = 20\ncamera_rays = 4\n";
    EXPECT(mcrt_scene_from_toml(toml, &bad) == MCRT_STATUS_INVALID_SCENE && bad == NULL, "q = 1.5 refused");
    EXPECT(strstr(mcrt_last_error(), "estimator.q = 1.5") != NULL, "the message names the field");
    printf("invalid scene: %s\n", mcrt_last_error());

    McrtSamples *samples = mcrt_samples_new();
    double four[4] = {0.1, 0.2, 0.3, 0.4};
    EXPECT(mcrt_samples_extend(samples, four, 4) == MCRT_STATUS_OK, "four values");
    EXPECT(mcrt_samples_merge(samples, samples) == MCRT_STATUS_OK && mcrt_samples_count(samples) == 8,
           "samples merged with themselves count twice");
    double negative[2] = {0.5, -1.0};
    EXPECT(mcrt_samples_extend(samples, negative, 2) == MCRT_STATUS_INVALID_SAMPLE, "a negative value refused");
    EXPECT(strstr(mcrt_last_error(), "-1") != NULL, "the message gives the value");
    EXPECT(mcrt_samples_extend(samples, NULL, 3) == MCRT_STATUS_INVALID_ARGUMENT, "null values refused");
    McrtCheckOptions options = mcrt_check_options_default();
    options.false_alarm_rate = 2.0;
    EXPECT(mcrt_check(prediction, samples, &options, &verdict) == MCRT_STATUS_INVALID_OPTION, "rate 2 refused");
    EXPECT(strstr(mcrt_last_error(), "false_alarm_rate = 2") != NULL, "the message names the option");
    EXPECT(mcrt_check(NULL, samples, NULL, &verdict) == MCRT_STATUS_INVALID_ARGUMENT, "null prediction refused");
    bad = (McrtScene *)&failures; /* an old pointer: a failed call must leave NULL */
    EXPECT(mcrt_scene_from_file("/no/such/scene.toml", &bad) == MCRT_STATUS_INVALID_SCENE && bad == NULL, "missing file");
    EXPECT(strstr(mcrt_last_error(), "/no/such/scene.toml: cannot read") != NULL, "the message names the path");

    /* Accessors given NULL: a neutral value and a message, never a crash. */
    EXPECT(isnan(mcrt_prediction_mean(NULL).value) && mcrt_samples_count(NULL) == 0, "null accessors");
    EXPECT(mcrt_verdict_passed(NULL) == 0 && strcmp(mcrt_verdict_text(NULL), "") == 0, "null verdict");
    EXPECT(strstr(mcrt_last_error(), "verdict: a null pointer") != NULL, "null named");
    mcrt_samples_free(samples);

    free(values);
    mcrt_prediction_free(prediction);
    mcrt_scene_free(scene);
    if (failures == 0) printf("C API: every expectation holds\n");
    return failures == 0 ? 0 : 1;
}
