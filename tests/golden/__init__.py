"""The golden recording: every built-in example's outputs through the command line and the Python
API, recorded before issue 21's restructuring moves anything, and held by tests/test_golden.py
(README.md in this folder)."""
