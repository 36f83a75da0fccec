// Shared by the test shaders, to check that includes are expanded.
uint scramble(uint i) { return i * 2654435761u; }
