/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The board table of this build: CMake's STM32F4_BOARD picks board_<name>.h and passes it
 * as STM32F4_BOARD_HEADER, so drivers include this file and never a board by name.
 */
#ifndef STM32F4_BOARD_H
#define STM32F4_BOARD_H

#ifndef STM32F4_BOARD_HEADER
#error "STM32F4_BOARD_HEADER is not set: configure with the stm32f4 preset (-DSTM32F4_BOARD=...)"
#endif
#include STM32F4_BOARD_HEADER

#endif /* STM32F4_BOARD_H */
