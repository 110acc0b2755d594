/* SPDX-License-Identifier: MIT */
/* Fixed-point helpers of the core: the table sine/cosine and binary-angle conversions. */
#include "slam/fixed.h"

/* Table: tools/gen_sin_table.py (begin). */
static const q1_30_t fix_sin_table[257] = {
    0,          6588356,    13176464,   19764076,   26350943,   32936819,   39521455,   46104602,
    52686014,   59265442,   65842639,   72417357,   78989349,   85558366,   92124163,   98686491,
    105245103,  111799753,  118350194,  124896179,  131437462,  137973796,  144504935,  151030634,
    157550647,  164064728,  170572633,  177074115,  183568930,  190056834,  196537583,  203010932,
    209476638,  215934457,  222384147,  228825464,  235258165,  241682010,  248096755,  254502159,
    260897982,  267283981,  273659918,  280025552,  286380643,  292724951,  299058239,  305380268,
    311690799,  317989595,  324276419,  330551034,  336813204,  343062693,  349299266,  355522689,
    361732726,  367929144,  374111709,  380280190,  386434353,  392573967,  398698801,  404808624,
    410903207,  416982319,  423045732,  429093217,  435124548,  441139496,  447137835,  453119340,
    459083786,  465030947,  470960600,  476872522,  482766489,  488642281,  494499676,  500338453,
    506158392,  511959275,  517740883,  523502998,  529245404,  534967884,  540670223,  546352205,
    552013618,  557654248,  563273883,  568872310,  574449320,  580004702,  585538248,  591049748,
    596538995,  602005783,  607449906,  612871159,  618269338,  623644239,  628995660,  634323400,
    639627258,  644907034,  650162530,  655393548,  660599890,  665781362,  670937767,  676068911,
    681174602,  686254647,  691308855,  696337036,  701339000,  706314559,  711263525,  716185713,
    721080937,  725949013,  730789757,  735602987,  740388522,  745146182,  749875788,  754577161,
    759250125,  763894504,  768510122,  773096806,  777654384,  782182683,  786681534,  791150767,
    795590213,  799999706,  804379079,  808728167,  813046808,  817334838,  821592095,  825818421,
    830013654,  834177638,  838310216,  842411232,  846480531,  850517961,  854523370,  858496606,
    862437520,  866345964,  870221790,  874064853,  877875009,  881652112,  885396022,  889106597,
    892783698,  896427186,  900036924,  903612776,  907154608,  910662286,  914135678,  917574653,
    920979082,  924348837,  927683790,  930983817,  934248793,  937478595,  940673101,  943832191,
    946955747,  950043650,  953095785,  956112036,  959092290,  962036435,  964944360,  967815955,
    970651112,  973449725,  976211688,  978936898,  981625251,  984276646,  986890984,  989468165,
    992008094,  994510675,  996975812,  999403415,  1001793390, 1004145648, 1006460100, 1008736660,
    1010975242, 1013175761, 1015338134, 1017462281, 1019548121, 1021595575, 1023604567, 1025575020,
    1027506862, 1029400018, 1031254418, 1033069992, 1034846671, 1036584389, 1038283080, 1039942680,
    1041563127, 1043144360, 1044686319, 1046188946, 1047652185, 1049075980, 1050460278, 1051805027,
    1053110176, 1054375676, 1055601479, 1056787540, 1057933813, 1059040255, 1060106826, 1061133483,
    1062120190, 1063066909, 1063973603, 1064840240, 1065666786, 1066453210, 1067199483, 1067905576,
    1068571464, 1069197120, 1069782521, 1070327646, 1070832474, 1071296985, 1071721163, 1072104991,
    1072448455, 1072751542, 1073014240, 1073236540, 1073418433, 1073559913, 1073660973, 1073721611,
    1073741824,
};
/* Table: tools/gen_sin_table.py (end). */

/* Fraction bits of an angle within one table interval: 30 bits a quadrant, 8 for the index. */
#define FIX_SIN_FRAC_BITS 22u

q1_30_t fix_sin(bam32_t a)
{
    uint32_t p = a & (FIX_BAM_QUARTER - 1u);
    if ((a & FIX_BAM_QUARTER) != 0u) {
        /* sin(90° + x) = sin(90° - x): mirror within the quadrant; p may become 2^30. */
        p = FIX_BAM_QUARTER - p;
    }
    uint32_t idx = p >> FIX_SIN_FRAC_BITS;
    uint32_t frac = p & ((1u << FIX_SIN_FRAC_BITS) - 1u);
    uint32_t v = (uint32_t)fix_sin_table[idx];
    if (frac != 0u) {
        /* idx < 256 here, so idx + 1 is inside the table. The slope is below 2^23 and never
         * negative (the table rises): an unsigned product, rounded to nearest, is the
         * signed one's value with fewer instructions (this runs several times a tick). */
        uint32_t slope = (uint32_t)fix_sin_table[idx + 1u] - v;
        v += (uint32_t)(((uint64_t)slope * frac + (1u << (FIX_SIN_FRAC_BITS - 1u))) >>
                        FIX_SIN_FRAC_BITS);
    }
    return (a & FIX_BAM_HALF) != 0u ? -(q1_30_t)v : (q1_30_t)v;
}

q1_30_t fix_cos(bam32_t a)
{
    return fix_sin(a + FIX_BAM_QUARTER);
}

#define FIX_MDEG_TURN 360000

bam32_t fix_bam_from_mdeg(int32_t mdeg)
{
    int32_t m = mdeg % FIX_MDEG_TURN;
    if (m < 0) {
        m += FIX_MDEG_TURN;
    }
    return (bam32_t)fix_muldiv_u64((uint32_t)m, (uint64_t)1 << 32, FIX_MDEG_TURN);
}

int32_t fix_bam_to_mdeg(bam32_t a)
{
    int64_t s = fix_bam_diff(a, 0u);
    return (int32_t)fix_round_shift(s * FIX_MDEG_TURN, 32u);
}

uint64_t fix_muldiv_u64(uint64_t a, uint64_t b, uint64_t c)
{
    /* The 128-bit product hi:lo from 32-bit halves. */
    uint64_t a_lo = (uint32_t)a;
    uint64_t a_hi = a >> 32;
    uint64_t b_lo = (uint32_t)b;
    uint64_t b_hi = b >> 32;
    uint64_t ll = a_lo * b_lo;
    uint64_t lh = a_lo * b_hi;
    uint64_t hl = a_hi * b_lo;
    uint64_t mid = (ll >> 32) + (uint32_t)lh + (uint32_t)hl;
    uint64_t lo = (mid << 32) | (uint32_t)ll;
    uint64_t hi = a_hi * b_hi + (lh >> 32) + (hl >> 32) + (mid >> 32);

    uint64_t half = c / 2u;
    lo += half;
    if (lo < half) {
        hi++;
    }
    if (hi >= c) {
        return UINT64_MAX;
    }
    /* Restoring division; the running remainder (carry:hi) stays below 2c. */
    uint64_t q = 0;
    for (unsigned i = 0; i < 64u; i++) {
        uint64_t carry = hi >> 63;
        hi = (hi << 1) | (lo >> 63);
        lo <<= 1;
        q <<= 1;
        if (carry != 0u || hi >= c) {
            hi -= c;
            q |= 1u;
        }
    }
    return q;
}

/* Leading zero bits of v != 0. */
static unsigned clz32(uint32_t v)
{
    unsigned n = 0;
    for (unsigned half = 16u; half != 0u; half /= 2u) {
        if ((v >> (32u - half)) == 0u) {
            n += half;
            v <<= half;
        }
    }
    return n;
}

/*
 * (u1·2^32 + u0) / v for u1 < v, with 32-bit hardware divisions: long division in base
 * 2^16 on the normalised divisor, each quotient digit estimated from the top digits and
 * corrected at most twice (Knuth, TAOCP vol. 2, 4.3.1, Algorithm D; the two-digit form of
 * Warren, Hacker's Delight, 2nd ed., 9-4, divlu).
 */
static uint32_t div_64_32(uint32_t u1, uint32_t u0, uint32_t v)
{
    const uint32_t b = 1u << 16;
    unsigned s = clz32(v);
    v <<= s;
    uint32_t vn1 = v >> 16;
    uint32_t vn0 = v & 0xFFFFu;
    uint32_t un32 = s == 0u ? u1 : (u1 << s) | (u0 >> (32u - s));
    uint32_t un10 = u0 << s;
    uint32_t un1 = un10 >> 16;
    uint32_t un0 = un10 & 0xFFFFu;

    uint32_t q1 = un32 / vn1;
    uint32_t rhat = un32 - q1 * vn1;
    while (q1 >= b || q1 * vn0 > b * rhat + un1) {
        q1--;
        rhat += vn1;
        if (rhat >= b) {
            break;
        }
    }
    uint32_t un21 = un32 * b + un1 - q1 * v; /* modulo 2^32: the true value fits */
    uint32_t q0 = un21 / vn1;
    rhat = un21 - q0 * vn1;
    while (q0 >= b || q0 * vn0 > b * rhat + un0) {
        q0--;
        rhat += vn1;
        if (rhat >= b) {
            break;
        }
    }
    return q1 * b + q0;
}

uint64_t fix_div_u64_soft(uint64_t n, uint64_t d)
{
    uint32_t n1 = (uint32_t)(n >> 32);
    uint32_t n0 = (uint32_t)n;
    if ((d >> 32) == 0u) {
        uint32_t v = (uint32_t)d;
        if (n1 == 0u) {
            return n0 / v;
        }
        uint32_t q1 = n1 / v;
        return ((uint64_t)q1 << 32) | div_64_32(n1 - q1 * v, n0, v);
    }
    /* d >= 2^32, so the quotient fits in 32 bits. Divide n/2 by d's top 32 bits (shifted up
     * to its leading one), scale back: the estimate is the quotient or one above it; step
     * down one and correct up (Hacker's Delight, 9-5, divDU). */
    unsigned s = clz32((uint32_t)(d >> 32));
    uint32_t v1 = (uint32_t)((d << s) >> 32);
    uint64_t half = n >> 1;
    uint64_t q = ((uint64_t)div_64_32((uint32_t)(half >> 32), (uint32_t)half, v1) << s) >> 31;
    if (q != 0u) {
        q--;
    }
    if (n - q * d >= d) {
        q++;
    }
    return q;
}

int64_t fix_div_s64_soft(int64_t n, int64_t d)
{
    uint64_t un = n < 0 ? 0u - (uint64_t)n : (uint64_t)n;
    uint64_t ud = d < 0 ? 0u - (uint64_t)d : (uint64_t)d;
    uint64_t q = fix_div_u64_soft(un, ud);
    return (n < 0) != (d < 0) ? (int64_t)(0u - q) : (int64_t)q;
}
