#!/usr/bin/env python3
"""The power-of-ten table of lib/host/c4gh_fmt.c, computed exactly (Python integers).

For each decimal exponent k the float32 formatter can need (-45..31), the 63-bit
g(k) = floor(10^-k * 2^(62 - r)), r = floor(log2(10^-k)), so 2^62 <= g(k) < 2^63.
It also checks the integer approximations of floor(q log10 2), floor(log10(3/4 2^q)) and
floor(e log2 10) the formatter uses, over every exponent they are used for.
Usage: python3 scripts/gen-f32-table.py > table.txt (paste into c4gh_fmt.c)."""
from fractions import Fraction

K_MIN, K_MAX = -45, 31


def floor_log2(x):
    r = x.numerator.bit_length() - x.denominator.bit_length()
    while Fraction(2) ** r > x:
        r -= 1
    while Fraction(2) ** (r + 1) <= x:
        r += 1
    return r


def main():
    for q in range(-149, 105):
        k = (q * 661971961083) >> 41
        assert Fraction(10) ** k <= Fraction(2) ** q < Fraction(10) ** (k + 1), q
        k3 = (q * 661971961083 - 274743187321) >> 41
        assert Fraction(10) ** k3 <= Fraction(3, 4) * Fraction(2) ** q < Fraction(10) ** (k3 + 1), q
        assert K_MIN <= k3 <= k <= K_MAX
    for k in range(K_MIN, K_MAX + 1):
        x = Fraction(10) ** (-k)
        r = floor_log2(x)
        assert ((-k) * 913124641741) >> 38 == r, k
        g = (x * Fraction(2) ** (62 - r)).__floor__()
        assert 2 ** 62 <= g < 2 ** 63
        print("    UINT64_C(0x%016X), /* k = %d */" % (g, k))


if __name__ == "__main__":
    main()
