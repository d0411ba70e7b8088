#pragma once
// SHA-256 digests (OpenSSL), as lowercase hex: chunk names and integrity checks.
#include <string>
#include <string_view>

struct evp_md_ctx_st;

namespace pathfarm::farm {

std::string sha256Hex(std::string_view bytes);

// A digest of bytes that arrive in pieces (a chunk streamed to or from disk).
class Sha256 {
 public:
  Sha256();
  ~Sha256();
  Sha256(const Sha256&) = delete;
  Sha256& operator=(const Sha256&) = delete;

  void update(std::string_view bytes);
  // The digest of everything updated so far; the object is spent after.
  std::string hex();

 private:
  evp_md_ctx_st* context_;
};

}  // namespace pathfarm::farm
