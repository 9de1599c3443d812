"""Tests of 3dvo-rd (python3 -m unittest, run from tools/rd; registered with ctest)."""
