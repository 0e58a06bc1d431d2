#include <stdio.h>
#include <unimesh.h>

int main(void) {
    um_context *ctx = NULL;
    if (um_context_create(&ctx) != UM_OK) return 1;
    int ok = um_version_number() == UM_VERSION_NUMBER;
    printf("consumer linked unimesh %s\n", um_version_string());
    um_context_destroy(ctx);
    return ok ? 0 : 1;
}
