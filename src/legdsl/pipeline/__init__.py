"""The stages put together: the compile driver (``compile``), generated modules written and kept
fresh (``generated``), the run session (``session``) with its ``--set``/``--path`` values
(``settings``) and printed summary (``report``), and the metrics of a run directory (``measure``).
``run`` keeps the runner's old names for existing importers."""
