/* libFuzzer harness for transfer functions from JSON (lc_tf_parse: SPEC.md's
 * TF, {"fields": [...]} and ParaView presets): the input, NUL-terminated,
 * is the JSON text. A failure must leave a message; a success must give a
 * TF with 1..LC_MAX_FIELDS fields whose points lc_tf_get_field returns. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <lanecast/lanecast.h>

static lc_device *device;

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    lc_device_desc dd = {.target = LC_TARGET_SCALAR, .threads = 1};
    if (lc_device_create(&dd, &device) != LC_OK) abort();
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *text = malloc(size + 1);
    if (!text) return 0;
    memcpy(text, data, size);
    text[size] = '\0';
    lc_tf *tf = NULL;
    lc_status s = lc_tf_parse(device, text, "fuzz.json", &tf);
    free(text);
    if (s == LC_OK) {
        int n = lc_tf_field_count(tf);
        if (n < 1 || n > LC_MAX_FIELDS) abort();
        for (int f = 0; f < n; f++) {
            lc_tf_field fld;
            if (lc_tf_get_field(tf, f, &fld) != LC_OK || fld.ncolor < 1 || fld.nopacity < 1) abort();
            float acc = 0.0f;
            for (int i = 0; i < 4 * fld.ncolor; i++) acc += fld.color[i];
            for (int i = 0; i < 2 * fld.nopacity; i++) acc += fld.opacity[i];
            if (acc != acc) abort(); /* a NaN got through lc_tf_create's checks */
        }
        lc_tf_destroy(tf);
    } else if (tf || !lc_last_error()[0] || s == LC_ERROR_INTERNAL) {
        fprintf(stderr, "fuzz: status %d, tf %p, message '%s'\n", (int)s, (void *)tf, lc_last_error());
        abort();
    }
    return 0;
}
