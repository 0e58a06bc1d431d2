/* Compiled as strict ISO C99 (-std=c99 -pedantic-errors -Werror): the public
 * header must need nothing beyond C99. Running it checks the macros too. */
#include "unimesh.h"

#include <stdio.h>

int main(void) {
    um_context *ctx = 0;
    um_status s = um_context_create(&ctx);
    int ok = s == UM_OK && um_version_number() == UM_VERSION_NUMBER;
    um_context_destroy(ctx);
    printf("%s\n", ok ? "1 passed, 0 failed" : "0 passed, 1 failed");
    return ok ? 0 : 1;
}
