/* Compiles the plugin ABI header as strict C (-std=c99 -pedantic -Werror)
 * and reports its layout so the C++ side can compare. */
#include "abi_layout.h"

#define FACET_ABI_PUT(value) out[n++] = (value);

size_t facet_c_layout(size_t* out) {
    size_t n = 0;
    FACET_ABI_LAYOUT(FACET_ABI_PUT)
    return n;
}
