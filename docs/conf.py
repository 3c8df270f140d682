"""Sphinx configuration of the radial_ibvs_gym documentation (``make docs``)."""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "agents"))  # radial_ibvs_agents
sys.path.insert(0, str(Path(__file__).resolve().parent))

from _env_pages import copy_notebooks, write_env_pages  # noqa: E402

from radial_ibvs_gym import __version__  # noqa: E402

project = "radial_ibvs_gym"
author = "radial_ibvs_gym developers"
copyright = "2026, radial_ibvs_gym developers"
release = version = __version__

extensions = [
    "myst_nb",  # MyST Markdown pages, and the notebooks rendered from their stored outputs
    "sphinx_design",  # the front page's cards
    "sphinx.ext.autodoc",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
]
source_suffix = {".md": "myst-nb", ".ipynb": "myst-nb", ".rst": "restructuredtext"}
nb_execution_mode = "off"  # the notebooks show the outputs stored in them (CI executes them)
#: outputs displayed as Markdown (``display(Markdown(table))``) are parsed as MyST, which has
#: tables; myst-nb's default, CommonMark, has none and shows a table as lines of pipes
nb_render_markdown_format = "myst"
exclude_patterns = ["_build", "Thumbs.db", ".DS_Store", "img/README.md"]
myst_enable_extensions = ["colon_fence", "dollarmath", "deflist"]
myst_heading_anchors = 3
html_theme = "furo"
html_title = f"radial_ibvs_gym {release}"
html_static_path = ["_static"]
html_css_files = ["wrap.css"]  # long command lines wrap
autodoc_member_order = "bysource"
autodoc_typehints = "description"
autodoc_default_options = {"members": True, "undoc-members": False, "show-inheritance": False}
napoleon_numpy_docstring = True
napoleon_google_docstring = False
napoleon_use_ivar = True  # dataclass Attributes as fields: no duplicate descriptions
suppress_warnings = ["myst.header"]

write_env_pages(Path(__file__).resolve().parent / "envs")
copy_notebooks(ROOT / "notebooks", Path(__file__).resolve().parent / "notebooks")
