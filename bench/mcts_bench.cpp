// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
int main() { return 0; }
