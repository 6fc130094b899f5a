/* SPDX-License-Identifier: MIT */
/* The shortest decimal text of a float32: the fewest significant digits that read back
 * (strtof, round to nearest) to the same float, bit for bit; of those, the one nearest the
 * float's exact value. Written like printf's %g (exponent when it is below -4 or above 8:
 * "0.1", "1000000", "1e-05", "3.4028235e+38"), so a float whose %.9g text is already the
 * shortest gets the same text. NaN is "nan" (either sign), infinities "inf" and "-inf",
 * as the CSV module writes them; -0 is "-0". */
#ifndef C4GH_FMT_H
#define C4GH_FMT_H

#include <stddef.h>

/** Room for the longest text and its NUL ("-1.17549435e-38"). */
#define C4GH_F32_TEXT_MAX 16U

/** Writes the shortest text of @p v and a NUL into @p buf (C4GH_F32_TEXT_MAX bytes; the
 *  bytes after the NUL may be overwritten too, never past C4GH_F32_TEXT_MAX).
 *  @return the text's length, without the NUL. */
size_t c4gh_fmt_f32(float v, char *buf);

#endif
