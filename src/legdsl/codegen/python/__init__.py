"""The Python target: the readable reference backend."""
