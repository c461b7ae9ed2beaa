/* Every message on the bus carries a tag: keyed BLAKE2b-256 (libsodium crypto_generichash) of
 * the channel name and the payload, with a key only this host's user can read. A datagram from
 * another machine (LCM's receive socket binds 0.0.0.0, and the multicast group is joined on the
 * routed interface) has no valid tag and is dropped before decoding. Several machines share a
 * pipeline by sharing the key file (docs/bus.md). */
#include "bus_private.h"

#include <errno.h>
#include <fcntl.h>
#include <sodium.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define KEY_BYTES BUS_TAG_BYTES /* 32 */

static unsigned char key[KEY_BYTES];
static int key_loaded;
static char key_path[600];

/* $TRYON_BUS_KEY_FILE, else $XDG_RUNTIME_DIR/tryon-bus.key, else ~/.cache/tryon/bus.key (the
 * folders made 0700). */
static int choose_path(char *err, size_t err_size)
{
    const char *env = getenv("TRYON_BUS_KEY_FILE"), *run = getenv("XDG_RUNTIME_DIR");
    const char *home = getenv("HOME");
    if (env && env[0]) {
        snprintf(key_path, sizeof key_path, "%s", env);
    } else if (run && run[0] == '/') {
        snprintf(key_path, sizeof key_path, "%s/tryon-bus.key", run);
    } else if (home && home[0] == '/') {
        char dir[520];
        snprintf(dir, sizeof dir, "%s/.cache", home);
        mkdir(dir, 0700);
        snprintf(dir, sizeof dir, "%s/.cache/tryon", home);
        mkdir(dir, 0700);
        snprintf(key_path, sizeof key_path, "%s/bus.key", dir);
    } else {
        snprintf(err, err_size, "no bus key file: set TRYON_BUS_KEY_FILE (or HOME)");
        return -1;
    }
    return 0;
}

/* A new random key, made under a temporary name and linked into place: when several stages
 * start at once, the first link wins and the others read its key. */
static int create_key(char *err, size_t err_size)
{
    char tmp[640];
    snprintf(tmp, sizeof tmp, "%s.%d.tmp", key_path, (int)getpid());
    int fd = open(tmp, O_WRONLY | O_CREAT | O_EXCL, 0600);
    if (fd < 0) {
        snprintf(err, err_size, "cannot create bus key %s: %s", tmp, strerror(errno));
        return -1;
    }
    unsigned char k[KEY_BYTES];
    randombytes_buf(k, sizeof k);
    int ok = write(fd, k, sizeof k) == (ssize_t)sizeof k;
    ok = close(fd) == 0 && ok;
    int linked = ok ? link(tmp, key_path) : -1;
    int link_errno = errno;
    unlink(tmp);
    sodium_memzero(k, sizeof k);
    if (!ok || (linked != 0 && link_errno != EEXIST)) {
        snprintf(err, err_size, "cannot create bus key %s: %s", key_path, strerror(link_errno));
        return -1;
    }
    return 0;
}

static int read_key(char *err, size_t err_size)
{
    int fd = open(key_path, O_RDONLY | O_NOFOLLOW);
    if (fd < 0) {
        snprintf(err, err_size, "cannot open bus key %s: %s", key_path, strerror(errno));
        return -1;
    }
    struct stat st;
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode) || st.st_uid != geteuid() ||
        (st.st_mode & 077) != 0) {
        snprintf(err, err_size,
                 "bus key %s must be a file of this user readable by nobody else "
                 "(chmod 600 %s)",
                 key_path, key_path);
        close(fd);
        return -1;
    }
    ssize_t n = read(fd, key, sizeof key);
    close(fd);
    if (n != (ssize_t)sizeof key) {
        snprintf(err, err_size, "bus key %s: %zd bytes, %d expected", key_path, n, KEY_BYTES);
        return -1;
    }
    return 0;
}

int bus_key_load(char *err, size_t err_size)
{
    if (key_loaded)
        return 0;
    if (sodium_init() < 0) {
        snprintf(err, err_size, "libsodium failed to initialise");
        return -BUS_ERR_AUTH;
    }
    if (choose_path(err, err_size) != 0)
        return -BUS_ERR_AUTH;
    if (access(key_path, F_OK) != 0 && create_key(err, err_size) != 0)
        return -BUS_ERR_AUTH;
    if (read_key(err, err_size) != 0)
        return -BUS_ERR_AUTH;
    key_loaded = 1;
    return 0;
}

const char *bus_key_path(void)
{
    return key_path;
}

/* The tag of channel (with its NUL, so "AB"+"C..." and "A"+"BC..." differ) and payload. */
static void tag_of(const char *channel, const uint8_t *payload, size_t len,
                   uint8_t tag[BUS_TAG_BYTES])
{
    crypto_generichash_state st;
    crypto_generichash_init(&st, key, sizeof key, BUS_TAG_BYTES);
    crypto_generichash_update(&st, (const unsigned char *)channel, strlen(channel) + 1);
    crypto_generichash_update(&st, payload, len);
    crypto_generichash_final(&st, tag, BUS_TAG_BYTES);
}

int bus_seal(const char *channel, uint8_t *buf, size_t len, bus_reject *why)
{
    char err[600];
    if (bus_key_load(err, sizeof err) != 0)
        return bus_reject_set(why, BUS_ERR_AUTH, "%.150s", err);
    tag_of(channel, buf, len, buf + len);
    return BUS_OK;
}

int bus_unseal(const char *channel, const uint8_t *buf, size_t len, size_t *payload_len,
               bus_reject *why)
{
    char err[600];
    if (bus_key_load(err, sizeof err) != 0)
        return bus_reject_set(why, BUS_ERR_AUTH, "%.150s", err);
    if (!buf || len < BUS_TAG_BYTES)
        return bus_reject_set(why, BUS_ERR_AUTH, "%zu bytes: no room for the tag", buf ? len : 0);
    uint8_t tag[BUS_TAG_BYTES];
    tag_of(channel, buf, len - BUS_TAG_BYTES, tag);
    if (sodium_memcmp(tag, buf + len - BUS_TAG_BYTES, BUS_TAG_BYTES) != 0)
        return bus_reject_set(why, BUS_ERR_AUTH, "tag does not match this host's key (%s)",
                              key_path);
    *payload_len = len - BUS_TAG_BYTES;
    return BUS_OK;
}

int bus_publish_raw(lcm_t *lcm, const char *channel, const void *payload, size_t len,
                    bus_reject *why)
{
    if (len > (size_t)INT32_MAX - BUS_TAG_BYTES)
        return bus_reject_set(why, BUS_ERR_COUNT, "%zu bytes", len);
    uint8_t *buf = malloc(len + BUS_TAG_BYTES);
    if (!buf)
        return bus_reject_set(why, BUS_ERR_NO_MEMORY, "%zu bytes", len);
    if (len)
        memcpy(buf, payload, len);
    int e = bus_seal(channel, buf, len, why);
    if (e == BUS_OK && lcm_publish(lcm, channel, buf, (unsigned)(len + BUS_TAG_BYTES)) != 0)
        e = bus_reject_set(why, BUS_ERR_PUBLISH, "%zu bytes on %s", len, channel);
    free(buf);
    return e;
}
