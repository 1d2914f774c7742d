// texsim command-line entry point (docs/cli.md).
#include <cstdio>

int main() {
  std::puts("texsim");
  return 0;
}
