/// \file test_pch.cpp
/// The program that owns the test programs' shared precompiled header (tests/CMakeLists.txt,
/// FLEXREF_TEST_PCH): an executable, so that the header is compiled as position-independent
/// executable code (-fPIE) like the test programs that reuse it. It does nothing.
int main() { return 0; }
