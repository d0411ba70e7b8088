// tinyobjloader's implementation compiled into the fuzzer, so the sanitizers see inside the
// OBJ parser too (the main build links Debian's libtinyobjloader instead).
#define TINYOBJLOADER_IMPLEMENTATION
#include <tiny_obj_loader.h>
