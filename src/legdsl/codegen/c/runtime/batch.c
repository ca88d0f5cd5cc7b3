/* batch.c: many copies of one run, each taken from start to end in C (legdsl.pipeline.batch).
 *
 * Python sets up one run's leg_sim, the template, and for each of its arrays a block that
 * holds every copy's own array (a structure of arrays: copy k's at base + k * stride; stride 0
 * shares the template's array, for one the run only reads). A copy is the template with its
 * pointers moved to its own arrays and some numbers replaced by its own (its start height),
 * run by leg_begin and leg_run exactly as a single run is, so its samples are a single run's.
 *
 * Any number of threads share a batch, each in a call of its own (ctypes lets go of the GIL):
 * a call takes the next copy nobody has taken until none is left. The template's buffers hold
 * the whole run, so leg_run returns only when the copy ends, at its step budget (then the
 * copy goes on unless the batch was told to stop: *stop, set by Python at Ctrl-C) or where
 * it would need Python (a tick the C machine hands over, the event buffer full): the copy
 * stops there with that code, and Python runs it again its own way.
 */
#include <stdint.h>
#include <string.h>

#include "legdsl_sim.h"
#include "legdsl_sizes.h"
#include "legdsl_model.h"

int64_t leg_begin(leg_sim *s);
int64_t leg_run(leg_sim *s);

/* One field of leg_sim that differs between copies: a pointer set to copy k's array at
 * base + k * stride, or a number (8 bytes) read from there. */
typedef struct {
    int64_t offset;   /* of the field in leg_sim */
    int64_t stride;   /* bytes from one copy's array or number to the next's */
    int64_t pointer;  /* 1: the field points to the array; 0: it takes the number */
    char *base;
} leg_copy_field;

/* Runs copies until none is left; returns how many this call ran. codes[k] is leg_run's last
 * code for copy k (LEG_RAISED from leg_begin too); copy k's struct, at the end, is at
 * copies + k * copy_stride. Two threads run copies k and k + 1 side by side, so each copy's
 * struct and arrays start on cache lines of their own (Python lays them out so): sharing one
 * would make the two cores take turns at it at every step. */
int64_t leg_run_copies(const leg_sim *tmpl, const leg_copy_field *fields, int64_t n_fields,
                       char *copies, int64_t copy_stride, int64_t *codes, int64_t n,
                       int64_t *next, const int64_t *stop) {
    int64_t ran = 0;
    for (;;) {
        if (__atomic_load_n(stop, __ATOMIC_RELAXED)) return ran;
        int64_t k = __atomic_fetch_add(next, 1, __ATOMIC_RELAXED);
        if (k >= n) return ran;
        leg_sim *s = (leg_sim *)(copies + k * copy_stride);
        memcpy(s, tmpl, sizeof *s);
        for (int64_t f = 0; f < n_fields; f++) {
            char *at = fields[f].base + k * fields[f].stride;
            if (fields[f].pointer)
                memcpy((char *)s + fields[f].offset, &at, sizeof at);
            else
                memcpy((char *)s + fields[f].offset, at, 8);
        }
        int64_t code = leg_begin(s);
        while (code == 0) {
            code = leg_run(s);
            if (code != LEG_YIELD || s->n_events + LEG_NC > s->event_cap) break; /* Python's */
            code = __atomic_load_n(stop, __ATOMIC_RELAXED) ? LEG_STOPPED : 0;
        }
        codes[k] = code;
        ran++;
    }
}
