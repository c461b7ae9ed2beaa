/* tryon-bus-check: proves that the LCM URL in use delivers a full 640x480 16-bit depth frame to
 * this very process. LCM drops large UDP messages silently when the receive buffer is small or
 * multicast has no route, so "it opened" is not enough. */
#include "bus.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define CHECK_W       640
#define CHECK_H       480
#define CHECK_TRIES   5
#define CHECK_WAIT_MS 400

typedef struct check_state {
    int got;
    int equal;
    const uint8_t *sent;
} check_state;

static void on_depth(const char *channel, const void *msg, void *user)
{
    (void)channel;
    const tryon_depth_frame_t *f = msg;
    check_state *st = user;
    st->got++;
    st->equal = f->num_bytes == CHECK_W * CHECK_H * 2 &&
                memcmp(f->data, st->sent, (size_t)f->num_bytes) == 0;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* --seal-cost: the time to sign, and to verify, one 640x480 16-bit frame (median of 200). */
static int seal_cost(void)
{
    enum { RUNS = 200, BYTES = CHECK_W * CHECK_H * 2 };
    static uint8_t buf[BYTES + BUS_TAG_BYTES];
    double seal_ms[RUNS], unseal_ms[RUNS];
    bus_reject why;
    for (size_t i = 0; i < BYTES; i++)
        buf[i] = (uint8_t)(i * 2654435761u >> 13);
    for (int r = 0; r < RUNS; r++) {
        int64_t t0 = bus_now_mono_us();
        int e = bus_seal("DEPTH", buf, BYTES, &why);
        int64_t t1 = bus_now_mono_us();
        size_t n;
        e = e != BUS_OK ? e : bus_unseal("DEPTH", buf, sizeof buf, &n, &why);
        int64_t t2 = bus_now_mono_us();
        if (e != BUS_OK) {
            fprintf(stderr, "tryon-bus-check: %s\n", why.detail);
            return 1;
        }
        seal_ms[r] = (double)(t1 - t0) / 1000.0;
        unseal_ms[r] = (double)(t2 - t1) / 1000.0;
    }
    qsort(seal_ms, RUNS, sizeof seal_ms[0], cmp_double);
    qsort(unseal_ms, RUNS, sizeof unseal_ms[0], cmp_double);
    printf("{\"bytes\": %d, \"runs\": %d, \"sign_ms_median\": %.3f, \"verify_ms_median\": %.3f}\n",
           BYTES, RUNS, seal_ms[RUNS / 2], unseal_ms[RUNS / 2]);
    return 0;
}

int main(int argc, char **argv)
{
    const char *url = argc > 1 ? argv[1] : NULL;
    if (url && (strcmp(url, "-h") == 0 || strcmp(url, "--help") == 0)) {
        printf("usage: tryon-bus-check [LCM_URL] | --print-url | --seal-cost\n"
               "Sends one 640x480 depth frame to itself over LCM (default: $TRYON_LCM_URL or %s)"
               "\nand says whether it arrived intact.\n"
               "  --print-url  print the URL the stages use here and exit (for lcm-logger)\n"
               "  --seal-cost  time signing and verifying one 640x480 depth frame (JSON)\n",
               BUS_DEFAULT_URL);
        return 0;
    }
    if (url && strcmp(url, "--seal-cost") == 0 && argc == 2) {
        char err[600];
        if (bus_key_load(err, sizeof err) != 0) {
            fprintf(stderr, "tryon-bus-check: %s\n", err);
            return 1;
        }
        return seal_cost();
    }
    if (url && strcmp(url, "--print-url") == 0 && argc == 2) {
        printf("%s\n", bus_default_url());
        return 0;
    }
    if (argc > 2 || (url && url[0] == '-')) {
        fprintf(stderr, "tryon-bus-check: unknown option %s (see --help)\n",
                argv[argc > 2 ? 2 : 1]);
        return 2;
    }
    char err[512];
    lcm_t *lcm = bus_open(url, err, sizeof err);
    if (!lcm) {
        fprintf(stderr, "tryon-bus-check: %s\n", err);
        return 1;
    }
    static uint8_t data[CHECK_W * CHECK_H * 2];
    for (size_t i = 0; i < sizeof data; i++)
        data[i] = (uint8_t)(i * 2654435761u >> 13);
    char channel[BUS_CHANNEL_MAX];
    snprintf(channel, sizeof channel, "TRYON_BUS_CHECK_%d", (int)getpid());
    check_state st = {.sent = data};
    bus_sub *sub = bus_subscribe(lcm, channel, BUS_DEPTH_FRAME, on_depth, &st);
    tryon_depth_frame_t f = {
        .source = "bus-check",
        .width = CHECK_W,
        .height = CHECK_H,
        .fx = 580,
        .fy = 580,
        .cx = 320,
        .cy = 240,
        .metres_per_unit = 0.001f,
        .camera_to_world = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1},
        .encoding = TRYON_DEPTH_FRAME_T_ENCODING_U16,
        .num_bytes = (int32_t)sizeof data,
        .data = data,
    };
    for (int i = 0; i < CHECK_TRIES && !st.got; i++) {
        bus_reject why;
        if (bus_publish(lcm, channel, BUS_DEPTH_FRAME, &f, &why) != BUS_OK) {
            fprintf(stderr, "tryon-bus-check: publish failed: %s\n", why.detail);
            break;
        }
        lcm_handle_timeout(lcm, CHECK_WAIT_MS);
    }
    int ok = st.got && st.equal;
    if (ok)
        printf("tryon-bus-check: a 640x480 depth frame (%zu bytes) looped back intact over %s\n",
               sizeof data, url ? url : bus_default_url());
    else
        fprintf(stderr,
                "tryon-bus-check: a 640x480 depth frame did %s over %s.\n"
                "  Check that the URL has recv_buf_size=8388608, that the kernel allows it\n"
                "  (sysctl net.core.rmem_max), and that multicast is routed: "
                "'sudo ip route add 224.0.0.0/4 dev lo'.\n",
                st.got ? "arrive corrupted" : "not arrive", url ? url : bus_default_url());
    bus_unsubscribe(lcm, sub);
    lcm_destroy(lcm);
    return ok ? 0 : 1;
}
