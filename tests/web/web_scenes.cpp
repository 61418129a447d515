// The comparison scenes run natively (tests/web/compare_native_wasm.py runs the same scenes in
// the WebAssembly module under node): web_scenes SCENE prints ajx::web::scene_report(SCENE).
#include <cstdio>
#include <exception>
#include <string>

#include "web/engine.hpp"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: web_scenes locked|climb|slack\n");
    return 2;
  }
  try {
    std::fputs(ajx::web::scene_report(argv[1]).c_str(), stdout);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
