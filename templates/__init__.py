"""Jinja templates of the code-generation backends (package data)."""
