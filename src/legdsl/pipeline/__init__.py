"""The stages put together: the compile driver, generated modules kept fresh, and the run session."""
