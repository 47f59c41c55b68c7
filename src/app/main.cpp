#include <cstdio>
int main() { std::puts("anamorph " ANAMORPH_VERSION); }
