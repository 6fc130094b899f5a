/* SPDX-License-Identifier: MIT */
/* Shared by the tool-parser fuzz targets: the input becomes an exact-size heap copy
 * (ASan reports any read past it), and every error message must be well formed. */
#ifndef FUZZ_TEXT_H
#define FUZZ_TEXT_H

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "c4gh_textfile.h"

static char *fuzz_copy(const uint8_t *data, size_t size)
{
    char *buf = malloc(size ? size : 1U);
    if (buf != NULL && size > 0U) {
        memcpy(buf, data, size);
    }
    return buf;
}

/* An error names the file first, fits its buffer, and carries no control byte but TAB
 * (input bytes reach the terminal only escaped). */
static void fuzz_check_err(const char *err, size_t cap, const char *path)
{
    size_t i;
    const size_t pl = strlen(path);
    if (memchr(err, '\0', cap) == NULL || strncmp(err, path, pl) != 0 ||
        err[pl] != ':' || strlen(err) < pl + 3U) {
        abort();
    }
    for (i = 0; err[i] != '\0'; i++) {
        if (((unsigned char)err[i] < 0x20U && err[i] != '\t') || (unsigned char)err[i] == 0x7FU) {
            abort();
        }
    }
}

#define FUZZ_FINITE_IN(x, lo, hi) do { if (!((x) >= (lo) && (x) <= (hi))) abort(); } while (0)

#endif
