/* Bad input to every implemented public function: the right lc_status, a
 * non-empty message (per thread and per device), the log callback called,
 * never an abort; destroying NULL is a no-op that raises no error. The volume
 * calls (lc_volume_*, lc_particles_*, lc_grid_*, lc_volume_load,
 * lc_file_probe, lc_format_get) with NULL and wrong-kind handles. lc_render
 * and lc_image_write are not called here. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "lanecast/lanecast.h"
#include "check.h"

typedef struct log_capture {
    int calls;
    lc_log_level level;
    char last[1024];
} log_capture;

static void capture(void *user, lc_log_level level, const char *message)
{
    log_capture *c = user;
    c->calls++;
    c->level = level;
    snprintf(c->last, sizeof c->last, "%s", message);
}

/* A failed call must return `want` and leave a message naming `needle`. */
#define EXPECT_ERROR(call, want, needle)                                                                             \
    do {                                                                                                             \
        lc_status s_ = (call);                                                                                       \
        const char *m_ = lc_last_error();                                                                            \
        CHECK(s_ == (want) && m_ && m_[0] && strstr(m_, needle), "%s -> %s: \"%s\"", #call, lc_status_string(s_),    \
              m_ ? m_ : "(null)");                                                                                   \
    } while (0)

static void status_and_version(void)
{
    static const lc_status codes[] = {LC_OK, LC_ERROR_INVALID_ARGUMENT, LC_ERROR_UNSUPPORTED, LC_ERROR_OUT_OF_MEMORY,
                                      LC_ERROR_IO, LC_ERROR_FORMAT, LC_ERROR_INTERNAL};
    for (size_t i = 0; i < sizeof codes / sizeof codes[0]; i++) {
        const char *s = lc_status_string(codes[i]);
        int distinct = 1;
        for (size_t j = 0; j < i; j++) distinct &= strcmp(s, lc_status_string(codes[j])) != 0;
        CHECK(s && s[0] && distinct && strcmp(s, "unknown status") != 0, "lc_status_string(%d) = \"%s\"", codes[i], s);
    }
    CHECK(strcmp(lc_status_string((lc_status)-99), "unknown status") == 0 &&
              strcmp(lc_status_string((lc_status)7), "unknown status") == 0,
          "lc_status_string of -99 and 7 = \"unknown status\"");
    int ma = -1, mi = -1, pa = -1;
    lc_version(&ma, &mi, &pa);
    CHECK(ma == LC_VERSION_MAJOR && mi == LC_VERSION_MINOR && pa == LC_VERSION_PATCH, "lc_version = %d.%d.%d", ma, mi,
          pa);
    lc_version(NULL, NULL, NULL);
    lc_version(&ma, NULL, NULL);
    CHECK(ma == LC_VERSION_MAJOR, "lc_version accepts NULL pointers");
    CHECK(strcmp(lc_version_string(), LC_VERSION_STRING) == 0, "lc_version_string = \"%s\"", lc_version_string());
}

static void targets(void)
{
    lc_target t;
    EXPECT_ERROR(lc_target_from_name(NULL, &t), LC_ERROR_INVALID_ARGUMENT, "NULL");
    EXPECT_ERROR(lc_target_from_name("scalar", NULL), LC_ERROR_INVALID_ARGUMENT, "NULL");
    EXPECT_ERROR(lc_target_from_name("", &t), LC_ERROR_INVALID_ARGUMENT, "known");
    EXPECT_ERROR(lc_target_from_name("neon", &t), LC_ERROR_INVALID_ARGUMENT, "neon");
    CHECK(!lc_target_compiled((lc_target)-3) && !lc_target_compiled((lc_target)77), "lc_target_compiled(-3, 77) = 0");
    CHECK(!lc_target_supported((lc_target)-3) && !lc_target_supported((lc_target)77), "lc_target_supported(-3, 77) = 0");
}

static void devices(void)
{
    log_capture log = {0};
    lc_device *dev = NULL;
    EXPECT_ERROR(lc_device_create(NULL, NULL), LC_ERROR_INVALID_ARGUMENT, "out");
    static const int bad_threads[] = {-1, 100000, 1025};
    for (size_t i = 0; i < sizeof bad_threads / sizeof bad_threads[0]; i++) {
        char num[16];
        snprintf(num, sizeof num, "%d", bad_threads[i]);
        log.calls = 0;
        lc_device_desc d = {.threads = bad_threads[i], .log = capture, .log_user = &log};
        EXPECT_ERROR(lc_device_create(&d, &dev), LC_ERROR_INVALID_ARGUMENT, num);
        CHECK(dev == NULL, "failed create leaves *out NULL");
        CHECK(log.calls == 1 && log.level == LC_LOG_ERROR && strcmp(log.last, lc_last_error()) == 0,
              "log callback got the error once at LC_LOG_ERROR: \"%s\"", log.last);
    }
    setenv("LANECAST_THREADS", "many", 1);
    EXPECT_ERROR(lc_device_create(NULL, &dev), LC_ERROR_INVALID_ARGUMENT, "many");
    setenv("LANECAST_THREADS", "0", 1);
    EXPECT_ERROR(lc_device_create(NULL, &dev), LC_ERROR_INVALID_ARGUMENT, "LANECAST_THREADS");
    unsetenv("LANECAST_THREADS");
    EXPECT_ERROR(lc_device_create(&(lc_device_desc){.target = (lc_target)42}, &dev), LC_ERROR_INVALID_ARGUMENT, "42");

    lc_target t;
    int n;
    EXPECT_ERROR(lc_device_target(NULL, &t), LC_ERROR_INVALID_ARGUMENT, "NULL");
    EXPECT_ERROR(lc_device_threads(NULL, &n), LC_ERROR_INVALID_ARGUMENT, "NULL");
    const char *m = lc_device_last_error(NULL);
    CHECK(m && m[0], "lc_device_last_error(NULL) is a message: \"%s\"", m ? m : "(null)");
    /* destroy(NULL) is a no-op: it returns, and records and logs no error */
    char before[1024];
    snprintf(before, sizeof before, "%s", lc_last_error());
    lc_device_destroy(NULL);
    lc_volume_destroy(NULL);
    lc_tf_destroy(NULL);
    CHECK(before[0] && strcmp(lc_last_error(), before) == 0,
          "lc_device_destroy(NULL), lc_volume_destroy(NULL), lc_tf_destroy(NULL) return and leave the last error "
          "\"%s\" alone", lc_last_error());

    log.calls = 0;
    lc_status s = lc_device_create(&(lc_device_desc){.threads = 2, .log = capture, .log_user = &log}, &dev);
    CHECK(s == LC_OK && dev, "lc_device_create with 2 threads");
    if (!dev) return;
    CHECK(log.calls >= 1 && log.level == LC_LOG_INFO, "log callback got creation info: \"%s\"", log.last);
    CHECK(lc_device_last_error(dev)[0] == '\0', "a new device has no last error");
    CHECK(lc_device_threads(dev, &n) == LC_OK && n == 2, "lc_device_threads = %d", n);
    log.calls = 0;
    EXPECT_ERROR(lc_device_target(dev, NULL), LC_ERROR_INVALID_ARGUMENT, "NULL");
    CHECK(strcmp(lc_device_last_error(dev), lc_last_error()) == 0 && log.calls == 1 && log.level == LC_LOG_ERROR,
          "device keeps the message and logs it: \"%s\"", lc_device_last_error(dev));
    EXPECT_ERROR(lc_device_threads(dev, NULL), LC_ERROR_INVALID_ARGUMENT, "NULL");
    lc_device_destroy(dev);
}

/* Transfer-function handles: counts, presets, destroy(NULL). */
static void tfs(void)
{
    lc_tf *tf = NULL;
    CHECK(lc_tf_field_count(NULL) == 0, "lc_tf_field_count(NULL) = 0");
    CHECK(lc_tf_preset(NULL, "heat", 3, 1.0f, &tf) == LC_OK && lc_tf_field_count(tf) == 3,
          "a 3-field preset has %d fields", lc_tf_field_count(tf));
    lc_tf_destroy(tf);
    lc_tf_destroy(NULL);
    EXPECT_ERROR(lc_tf_preset(NULL, "heat", 9, 1.0f, &tf), LC_ERROR_INVALID_ARGUMENT, "9 fields");
    EXPECT_ERROR(lc_tf_preset(NULL, "nosuch", 1, 1.0f, &tf), LC_ERROR_INVALID_ARGUMENT, "nosuch");
    lc_feature_info json = {0};
    for (int i = 0; i < lc_feature_count(); i++)
        if (lc_feature_get(i, &json) == LC_OK && !strcmp(json.name, "json")) break;
    if (json.available)
        EXPECT_ERROR(lc_tf_parse(NULL, "{\"color\": [[0,1,1,1]]}", "t.json", &tf), LC_ERROR_FORMAT, "opacity");
    else /* compiled out: one line naming the package */
        EXPECT_ERROR(lc_tf_parse(NULL, "{\"color\": [[0,1,1,1]]}", "t.json", &tf), LC_ERROR_UNSUPPORTED, "libjson-c-dev");
}

/* The volume calls: NULL arguments, wrong kinds, bad names and indices. */
static void volumes(void)
{
    log_capture log = {0};
    lc_device *dev = NULL;
    if (lc_device_create(&(lc_device_desc){.threads = 1, .log = capture, .log_user = &log}, &dev) != LC_OK) {
        CHECK(0, "lc_device_create: %s", lc_last_error());
        return;
    }
    CHECK(lc_volume_kind(NULL) == LC_KIND_NONE, "lc_volume_kind(NULL) = LC_KIND_NONE");
    CHECK(!strcmp(lc_kind_name(LC_KIND_PARTICLES), "particles") && !strcmp(lc_kind_name(LC_KIND_GRID), "grid") &&
              lc_kind_name(LC_KIND_NONE) == NULL && lc_kind_name(LC_KIND_COUNT) == NULL &&
              lc_kind_name((lc_kind)-1) == NULL,
          "lc_kind_name: particles, grid; NULL for NONE, COUNT, -1");
    lc_volume_info vi;
    lc_particles_info pi;
    lc_grid_info gi;
    float pt[3] = {0, 0, 0}, val[1];
    EXPECT_ERROR(lc_volume_get_info(NULL, &vi), LC_ERROR_INVALID_ARGUMENT, "NULL");
    EXPECT_ERROR(lc_particles_get_info(NULL, &pi), LC_ERROR_INVALID_ARGUMENT, "NULL");
    EXPECT_ERROR(lc_grid_get_info(NULL, &gi), LC_ERROR_INVALID_ARGUMENT, "NULL");
    EXPECT_ERROR(lc_particles_set_params(NULL, NULL), LC_ERROR_INVALID_ARGUMENT, "NULL");
    EXPECT_ERROR(lc_grid_set_params(NULL, NULL), LC_ERROR_INVALID_ARGUMENT, "NULL");
    EXPECT_ERROR(lc_volume_sample(dev, NULL, 1, pt, val, NULL), LC_ERROR_INVALID_ARGUMENT, "NULL");

    /* one volume of each kind */
    lc_volume *p = NULL, *g = NULL;
    CHECK(lc_particles_create(dev, &(lc_particles_desc){.count = 1, .positions = pt, .radius = 1.0f}, &p) == LC_OK,
          "a particle volume");
    uint8_t vox[8] = {0, 1, 2, 3, 4, 5, 6, 7};
    CHECK(lc_grid_create(dev, &(lc_grid_desc){.size = {2, 2, 2}, .type = LC_VALUE_UINT8, .data = vox}, &g) == LC_OK,
          "a grid volume");
    if (!p || !g) {
        lc_volume_destroy(p);
        lc_volume_destroy(g);
        lc_device_destroy(dev);
        return;
    }
    EXPECT_ERROR(lc_volume_get_info(p, NULL), LC_ERROR_INVALID_ARGUMENT, "NULL");
    EXPECT_ERROR(lc_particles_get_info(p, NULL), LC_ERROR_INVALID_ARGUMENT, "out is NULL");
    EXPECT_ERROR(lc_grid_get_info(g, NULL), LC_ERROR_INVALID_ARGUMENT, "out is NULL");
    /* a kind-specific call on the other kind fails, naming the function and both kinds */
    log.calls = 0;
    EXPECT_ERROR(lc_grid_get_info(p, &gi), LC_ERROR_INVALID_ARGUMENT, "lc_grid_get_info: the volume holds particles, not grid");
    CHECK(log.calls == 1 && log.level == LC_LOG_ERROR && strcmp(lc_device_last_error(dev), lc_last_error()) == 0,
          "the wrong-kind error goes to the volume's device and its log: \"%s\"", lc_device_last_error(dev));
    EXPECT_ERROR(lc_particles_get_info(g, &pi), LC_ERROR_INVALID_ARGUMENT, "the volume holds grid, not particles");
    EXPECT_ERROR(lc_particles_set_params(g, &(lc_particle_params){.sigma = 3}), LC_ERROR_INVALID_ARGUMENT,
                 "lc_particles_set_params");
    EXPECT_ERROR(lc_grid_set_params(p, &(lc_grid_params){.delta_c = -1}), LC_ERROR_INVALID_ARGUMENT,
                 "lc_grid_set_params");
    /* bad parameters are refused and leave the current ones */
    EXPECT_ERROR(lc_particles_set_params(p, &(lc_particle_params){.sigma = -1}), LC_ERROR_INVALID_ARGUMENT, "sigma");
    EXPECT_ERROR(lc_particles_set_params(p, &(lc_particle_params){.kappa = NAN}), LC_ERROR_INVALID_ARGUMENT, "kappa");
    EXPECT_ERROR(lc_particles_set_params(p, &(lc_particle_params){.buffer_samples = -2}), LC_ERROR_INVALID_ARGUMENT,
                 "buffer");
    EXPECT_ERROR(lc_particles_set_params(p, &(lc_particle_params){.sphere_scale = -1}), LC_ERROR_INVALID_ARGUMENT,
                 "sphere");
    CHECK(lc_particles_get_info(p, &pi) == LC_OK && pi.params.sigma == 2.0f && pi.params.kappa == 1.0f,
          "after refused parameters the defaults remain (sigma %g, kappa %g)", (double)pi.params.sigma,
          (double)pi.params.kappa);
    EXPECT_ERROR(lc_grid_set_params(g, &(lc_grid_params){.rda = -0.5f}), LC_ERROR_INVALID_ARGUMENT, "rda");
    EXPECT_ERROR(lc_grid_set_params(g, &(lc_grid_params){.delta_p = INFINITY}), LC_ERROR_INVALID_ARGUMENT, "finite");
    CHECK(lc_grid_get_info(g, &gi) == LC_OK && gi.params.rda == 0.0f && gi.params.delta_p == 0.0f,
          "after refused grid parameters the old ones remain");
    EXPECT_ERROR(lc_volume_sample(NULL, g, 1, pt, val, NULL), LC_ERROR_INVALID_ARGUMENT, "device");
    EXPECT_ERROR(lc_volume_sample(dev, g, 1, NULL, val, NULL), LC_ERROR_INVALID_ARGUMENT, "NULL");
    EXPECT_ERROR(lc_volume_sample(dev, g, 1, pt, NULL, NULL), LC_ERROR_INVALID_ARGUMENT, "NULL");
    CHECK(lc_volume_sample(dev, g, 0, NULL, NULL, NULL) == LC_OK, "lc_volume_sample of 0 points with NULL arrays");
    /* creation */
    lc_volume *out = (lc_volume *)&log;
    EXPECT_ERROR(lc_grid_create(NULL, &(lc_grid_desc){.size = {2, 2, 2}, .type = LC_VALUE_UINT8, .data = vox}, &out),
                 LC_ERROR_INVALID_ARGUMENT, "device is NULL");
    CHECK(out == NULL, "failed lc_grid_create leaves *out NULL");
    EXPECT_ERROR(lc_grid_create(dev, NULL, &out), LC_ERROR_INVALID_ARGUMENT, "NULL");
    EXPECT_ERROR(lc_grid_create(dev, &(lc_grid_desc){.size = {2, 1, 2}, .type = LC_VALUE_UINT8, .data = vox}, &out),
                 LC_ERROR_INVALID_ARGUMENT, "at least 2");
    EXPECT_ERROR(lc_particles_create(NULL, &(lc_particles_desc){0}, &out), LC_ERROR_INVALID_ARGUMENT, "device is NULL");
    /* files */
    EXPECT_ERROR(lc_volume_load(NULL, "x.xyz", NULL, &out), LC_ERROR_INVALID_ARGUMENT, "device is NULL");
    EXPECT_ERROR(lc_volume_load(dev, NULL, NULL, &out), LC_ERROR_INVALID_ARGUMENT, "path is NULL");
    EXPECT_ERROR(lc_volume_load(dev, "x.xyz", NULL, NULL), LC_ERROR_INVALID_ARGUMENT, "out is NULL");
    EXPECT_ERROR(lc_volume_load(dev, "/nonexistent/x.xyz", NULL, &out), LC_ERROR_IO, "/nonexistent/x.xyz");
    CHECK(out == NULL, "failed lc_volume_load leaves *out NULL");
    EXPECT_ERROR(lc_volume_load(dev, "x.xyz", &(lc_load_desc){.noptions = 2}, &out), LC_ERROR_INVALID_ARGUMENT,
                 "options");
    lc_file_info fi;
    EXPECT_ERROR(lc_file_probe(NULL, NULL, NULL, &fi), LC_ERROR_INVALID_ARGUMENT, "NULL");
    EXPECT_ERROR(lc_file_probe(NULL, "x.xyz", NULL, NULL), LC_ERROR_INVALID_ARGUMENT, "NULL");
    EXPECT_ERROR(lc_file_probe(NULL, "/nonexistent/x.xyz", NULL, &fi), LC_ERROR_IO, "cannot open");
    lc_format_info fmt;
    int nformats = lc_format_count();
    EXPECT_ERROR(lc_format_get(-1, &fmt), LC_ERROR_INVALID_ARGUMENT, "-1");
    EXPECT_ERROR(lc_format_get(nformats, &fmt), LC_ERROR_INVALID_ARGUMENT, "index");
    EXPECT_ERROR(lc_format_get(0, NULL), LC_ERROR_INVALID_ARGUMENT, "NULL");
    lc_volume_destroy(p);
    lc_volume_destroy(g);
    lc_device_destroy(dev);
}

int main(void)
{
    unsetenv("LANECAST_TARGET");
    unsetenv("LANECAST_THREADS");
    unsetenv("LANECAST_CPU_MASK");
    CHECK(lc_last_error() && lc_last_error()[0] == '\0', "lc_last_error() is \"\" before any error");
    status_and_version();
    targets();
    devices();
    tfs();
    volumes();
    return check_summary("test_api_errors");
}
