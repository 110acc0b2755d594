/* SPDX-License-Identifier: MIT */
/*
 * The HAL's answers for what a backend does not have: no map storage (size 0 and
 * HAL_ENOSYS, as hal.h documents), no command input (hal_uart_read() never receives a
 * byte), only the paper's servo and sonar (each count 1), no bump switches (count 0,
 * HAL_ENOSYS), and no way to tell whether the UART has a listener (hal_uart_has_reader():
 * it may). Each definition is weak, so a backend that
 * has the feature defines the call and its definition wins; one that lacks it links this
 * library and leaves the call out.
 *
 * A backend's definition wins whichever side of this library it is linked on when it sits
 * in an object file the link takes anyway: a source of the program, or the archive member
 * that also holds a call the program needs (one file for the whole HAL, as the template);
 * tests/hal/weak_link_order.cmake checks both orders with gcc, clang and arm-none-eabi-gcc.
 * An archive member that holds nothing but overrides is taken only when the link reaches
 * it while the call is still undefined, so never after this library, whose weak definitions
 * answer first. A backend library therefore links hal_unsupported itself
 * (target_link_libraries(<backend> PUBLIC hal_unsupported)), which puts it after the
 * backend on every link line.
 */
#include "hal/hal.h"

__attribute__((weak)) size_t hal_uart_read(uint8_t *data, size_t len)
{
    (void)data;
    (void)len;
    return 0u;
}

__attribute__((weak)) bool hal_uart_has_reader(void)
{
    return true;
}

__attribute__((weak)) size_t hal_storage_size(void)
{
    return 0u;
}

__attribute__((weak)) int hal_storage_begin(uint8_t slot)
{
    (void)slot;
    return HAL_ENOSYS;
}

__attribute__((weak)) int hal_storage_write(uint8_t slot, uint32_t offset, const void *data,
                                            size_t len)
{
    (void)slot;
    (void)offset;
    (void)data;
    (void)len;
    return HAL_ENOSYS;
}

__attribute__((weak)) int hal_storage_commit(uint8_t slot)
{
    (void)slot;
    return HAL_ENOSYS;
}

__attribute__((weak)) int hal_storage_read(uint8_t slot, uint32_t offset, void *data, size_t len)
{
    (void)slot;
    (void)offset;
    (void)data;
    (void)len;
    return HAL_ENOSYS;
}

/* The paper's servo and sonar, instance 0 of each, and no other. */
__attribute__((weak)) uint8_t hal_servo_count(void)
{
    return 1u;
}

__attribute__((weak)) uint8_t hal_sonar_count(void)
{
    return 1u;
}

__attribute__((weak)) uint8_t hal_bump_count(void)
{
    return 0u;
}

__attribute__((weak)) int hal_bump_read(uint8_t bump, bool *pressed)
{
    (void)bump;
    (void)pressed;
    return HAL_ENOSYS;
}
