/* Bad input to every implemented public function: the right lc_status, a
 * non-empty message (per thread and per device), the log callback called,
 * never an abort. lc_tf_*, lc_render and lc_image_write are not implemented
 * yet and are not called here. */
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
    lc_device_destroy(NULL);
    CHECK(1, "lc_device_destroy(NULL) returns");

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
    EXPECT_ERROR(lc_tf_parse(NULL, "{\"color\": [[0,1,1,1]]}", "t.json", &tf), LC_ERROR_FORMAT, "opacity");
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
    return check_summary("test_api_errors");
}
