/* A sender from another machine: one wire-valid BODY as a raw LCM datagram (the "LC02" short
 * message: magic, sequence number, channel, payload) to an address and port, without going
 * through LCM, signed with the bus key only when asked.
 *   bus_udp_send ADDRESS PORT CHANNEL SEQ sign|plain */
#include <arpa/inet.h>
#include <netinet/in.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "bus.h"
#include "fixtures.h"

#define LCM_SHORT_MAGIC 0x4c433032u

int main(int argc, char **argv)
{
    static const char usage[] = "usage: bus_udp_send ADDRESS PORT CHANNEL SEQ sign|plain\n";
    if (argc > 1 && (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h"))) {
        fputs(usage, stdout);
        return 0;
    }
    if (argc != 6 || (strcmp(argv[5], "sign") != 0 && strcmp(argv[5], "plain") != 0)) {
        if (argc > 1 && argv[1][0] == '-')
            fprintf(stderr, "bus_udp_send: unknown option %s\n", argv[1]);
        fputs(usage, stderr);
        return 2;
    }
    fx_body b;
    fx_body_make(&b, 40, 30, atoi(argv[4]));
    b.msg.seq = atoi(argv[4]);
    uint8_t *payload;
    int n = fx_encode(BUS_BODY, &b.msg, &payload);
    size_t chlen = strlen(argv[3]) + 1, len = 8 + chlen + (size_t)n + BUS_TAG_BYTES;
    uint8_t *pkt = calloc(1, len);
    if (n <= 0 || !pkt)
        return 1;
    uint32_t magic = htonl(LCM_SHORT_MAGIC), seqno = htonl((uint32_t)b.msg.seq);
    memcpy(pkt, &magic, 4);
    memcpy(pkt + 4, &seqno, 4);
    memcpy(pkt + 8, argv[3], chlen);
    memcpy(pkt + 8 + chlen, payload, (size_t)n);
    size_t body_len = (size_t)n;
    if (strcmp(argv[5], "sign") == 0) {
        bus_reject why;
        if (bus_seal(argv[3], pkt + 8 + chlen, (size_t)n, &why) != BUS_OK) {
            fprintf(stderr, "bus_udp_send: %s\n", why.detail);
            return 1;
        }
        body_len += BUS_TAG_BYTES;
    }
    struct sockaddr_in to = {.sin_family = AF_INET, .sin_port = htons((uint16_t)atoi(argv[2]))};
    int fd = socket(AF_INET, SOCK_DGRAM, 0);
    if (fd < 0 || inet_pton(AF_INET, argv[1], &to.sin_addr) != 1)
        return 1;
    ssize_t sent = sendto(fd, pkt, 8 + chlen + body_len, 0, (struct sockaddr *)&to, sizeof to);
    close(fd);
    free(pkt);
    free(payload);
    fx_body_free(&b);
    if (sent < 0) {
        perror("bus_udp_send: sendto");
        return 1;
    }
    return 0;
}
