"""Cross-checks against other programs that run in environments of their own (.venv-arlpy)."""
