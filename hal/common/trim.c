/* SPDX-License-Identifier: MIT */
/* Trimming white space off text in place: for the line parsers of config files and maps. */
#include <ctype.h>
#include <string.h>

#include "hal_common/config_text.h"

char *cfgtext_trim(char *s)
{
    while (isspace((unsigned char)*s)) {
        s++;
    }
    size_t n = strlen(s);
    while (n > 0u && isspace((unsigned char)s[n - 1u])) {
        s[--n] = '\0';
    }
    return s;
}
