// Per-iteration results the CPU reads back with the messages.
layout(std430, binding = 1) buffer Counters {
  uint maxSpeedBits;  // floatBitsToUint(max |F|): ordered like the floats for non-negative values
  int signChanges;
  float dt;
  uint unused;
};
