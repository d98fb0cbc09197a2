/* What the FMI 2.0 and 3.0 frameworks (fmi2.c, fmi3.c) share: the identity and framing of
 * serialized FMU states, the log categories, and the checks that know no FMI type.
 * Included by each after config.h (MODEL_IDENTIFIER, MODEL_GUID). */
#ifndef LINKAGE_FMU_FMI_COMMON_H
#define LINKAGE_FMU_FMI_COMMON_H

#include <stdint.h>
#include <string.h>

/* identity of this model's states in memory: the address is unique to this binary */
static const char THIS_MODEL[] = MODEL_GUID;

#define STATE_FORMAT 1u
static const char STATE_MAGIC[8] = {'L', 'K', 'F', 'M', 'U', 'S', 'T', '\0'};

static const char *LOG_CATEGORIES[] = {"logStatusWarning", "logStatusDiscard",
                                       "logStatusError", "logStatusFatal", "logAll"};
#define N_CATEGORIES (sizeof LOG_CATEGORIES / sizeof *LOG_CATEGORIES)

/* 1 if `s` is well-formed UTF-8. */
static int utf8(const unsigned char *s) {
    while (*s) {
        unsigned c = *s++, n;
        uint32_t cp;
        if (c < 0x80) continue;
        if (c >= 0xC2 && c <= 0xDF) n = 1, cp = c & 0x1F;
        else if (c >= 0xE0 && c <= 0xEF) n = 2, cp = c & 0x0F;
        else if (c >= 0xF0 && c <= 0xF4) n = 3, cp = c & 0x07;
        else return 0;
        for (unsigned k = 0; k < n; k++, s++) {
            if ((*s & 0xC0) != 0x80) return 0;
            cp = cp << 6 | (*s & 0x3F);
        }
        if ((n == 2 && cp < 0x800) || (n == 3 && (cp < 0x10000 || cp > 0x10FFFF)) ||
            (cp >= 0xD800 && cp <= 0xDFFF))
            return 0;
    }
    return 1;
}

/* Serialized layout: magic[8] | u32 format | u32 nid | id | u32 nguid | guid | f64 time |
 * u64 n | payload[n] (the backend's) | u32 CRC-32 of all bytes before it. */
static uint32_t crc32(const unsigned char *p, size_t n) {
    uint32_t crc = 0xFFFFFFFFu;
    while (n--) {
        crc ^= *p++;
        for (int k = 0; k < 8; k++) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
    }
    return ~crc;
}

static size_t header_size(void) {
    return 8 + 4 + 4 + strlen(MODEL_IDENTIFIER) + 4 + strlen(MODEL_GUID) + 8 + 8;
}

static unsigned char *put(unsigned char *p, const void *v, size_t n) {
    memcpy(p, v, n);
    return p + n;
}

#endif
