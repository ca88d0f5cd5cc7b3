"""The names the runner had before it was split, for code that still imports them from here.

New code imports from where they live: ``legdsl.pipeline.session`` (the run session and the
run directory), ``legdsl.pipeline.generated`` (fresh-or-compile loading), ``legdsl.pipeline.settings``
(``--set`` and ``--path``) and ``legdsl.pipeline.report`` (what a run prints).
"""

from legdsl.pipeline.generated import import_module_file, load_controller, load_dynamics
from legdsl.pipeline.report import path_summary, progress_bar, summary
from legdsl.pipeline.settings import Settings, parse_path_option, parse_setting, sort_settings

__all__ = [
    "Settings",
    "import_module_file",
    "load_controller",
    "load_dynamics",
    "parse_path_option",
    "parse_setting",
    "path_summary",
    "progress_bar",
    "sort_settings",
    "summary",
]
