/* SPDX-License-Identifier: MIT */
/* Test of the frames' CRC against the bit-at-a-time definition: built twice, once as the
 * core is built here and once with the nibble table the MCU uses, so both tables are held
 * to the same CRC on every host. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "slam/telemetry.h"
#include "test_rng.h"

/* CRC-16/CCITT-FALSE as its definition states it: polynomial 0x1021, register 0xFFFF, each
 * byte's bits from the top, no reflection, no final XOR. */
static uint16_t crc_by_bits(const uint8_t *data, size_t len)
{
    uint16_t crc = 0xFFFFu;
    for (size_t i = 0; i < len; i++) {
        crc = (uint16_t)(crc ^ (uint16_t)(data[i] << 8));
        for (int bit = 0; bit < 8; bit++) {
            crc = (uint16_t)((crc & 0x8000u) != 0u ? (uint32_t)(crc << 1) ^ 0x1021u
                                                   : (uint32_t)(crc << 1));
        }
    }
    return crc;
}

static void test_crc16_check_value(void **state)
{
    (void)state;
    assert_int_equal(telem_crc16((const uint8_t *)"123456789", 9u), 0x29B1u);
    assert_int_equal(telem_crc16(NULL, 0u), 0xFFFFu);
}

/* Every byte value in every position, and random buffers of every frame length. */
static void test_crc16_matches_the_definition(void **state)
{
    (void)state;
    uint8_t buf[TELEM_FRAME_MAX];
    for (unsigned v = 0; v < 256u; v++) {
        for (size_t at = 0; at < 4u; at++) {
            memset(buf, 0xA5, sizeof buf);
            buf[at] = (uint8_t)v;
            assert_int_equal(telem_crc16(buf, 4u), crc_by_bits(buf, 4u));
        }
    }
    test_rng_t rng = {31u};
    for (int round = 0; round < 20; round++) {
        for (size_t len = 0; len <= sizeof buf; len++) {
            for (size_t i = 0; i < len; i++) {
                buf[i] = (uint8_t)test_rng_u64(&rng);
            }
            assert_int_equal(telem_crc16(buf, len), crc_by_bits(buf, len));
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_crc16_check_value),
        cmocka_unit_test(test_crc16_matches_the_definition),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
