// The GLSL twin of levelset/simple_point.cpp's isSimplePoint, line for line; its masks come from
// there as defines (CUBE_X0 .. CUBE_N26), so the two cannot drift apart.
uint alongX(uint m) { return m | ((m & ~CUBE_X2) << 1) | ((m & ~CUBE_X0) >> 1); }
uint alongY(uint m) { return m | ((m & ~CUBE_Y2) << 3) | ((m & ~CUBE_Y0) >> 3); }
uint alongZ(uint m) { return m | ((m & ~CUBE_Z2) << 9) | ((m & ~CUBE_Z0) >> 9); }
uint grow6(uint m) { return alongX(m) | alongY(m) | alongZ(m); }
uint grow18(uint m) { return alongX(alongY(m)) | alongX(alongZ(m)) | alongY(alongZ(m)); }

int componentsUpToTwo(uint set, bool by18) {
  int count = 0;
  while (set != 0u && count < 2) {
    uint part = set & (~set + 1u);
    for (uint next = (by18 ? grow18(part) : grow6(part)) & set; next != part; next = (by18 ? grow18(part) : grow6(part)) & set)
      part = next;
    set &= ~part;
    ++count;
  }
  return count;
}

bool isSimplePoint(uint inside) {
  uint object = inside & CUBE_N26;
  uint near = object & CUBE_N6;
  near |= grow6(near) & object & CUBE_N18;
  near |= grow6(near) & object;
  if (componentsUpToTwo(near, false) != 1) return false;
  uint background = ~inside & CUBE_N26;
  uint around = background & CUBE_N18;
  around |= grow18(around) & background;
  return componentsUpToTwo(around, true) == 1;
}
