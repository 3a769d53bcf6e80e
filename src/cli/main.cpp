// hemicontact command line (work in progress: the solve driver is being assembled).
#include <cstdio>
int main() {
  std::puts("hemicontact: usage: hemicontact solve SCENE.json [--out DIR] [--set path=value ...]");
  return 1;
}
