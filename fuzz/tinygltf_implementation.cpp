// tinygltf's implementation compiled into the fuzzer, so the sanitizers see inside the
// parser too (the main build links Debian's libtinygltf instead).
#define TINYGLTF_IMPLEMENTATION
#include <tiny_gltf.h>
