"""Backends: Kernels (and the Robot) in, ``{relative path: text}`` out; nothing is written here."""
