/* SPDX-License-Identifier: MIT */
/*
 * The pieces weak_link_order.cmake links, one per macro: a core that calls the HAL
 * (PROBE_CORE), a backend in one file (PROBE_BACKEND, with map storage or without:
 * PROBE_STORAGE), and a program whose own file may define storage (PROBE_MAIN).
 */
#include "hal/hal.h"

int probe_core(void);

#if defined(PROBE_CORE)
int probe_core(void)
{
    uint8_t b;
    return hal_init() + (int)hal_storage_size() + hal_storage_begin(0u) +
           (int)hal_uart_read(&b, 1u);
}
#endif

#if defined(PROBE_BACKEND)
int hal_init(void)
{
    return HAL_OK;
}
#endif

#if (defined(PROBE_BACKEND) || defined(PROBE_MAIN)) && defined(PROBE_STORAGE)
size_t hal_storage_size(void)
{
    return 4096u;
}

int hal_storage_begin(uint8_t slot)
{
    return slot < HAL_STORAGE_SLOTS ? HAL_OK : HAL_EINVAL;
}
#endif

#if defined(PROBE_MAIN)
int main(void);
int main(void)
{
    return probe_core();
}
#endif
