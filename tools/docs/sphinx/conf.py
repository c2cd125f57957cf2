# Sphinx configuration of taskmap's generated reference (tools/docs/reference.py copies this
# folder into the build's docs/src, adds cli.rst, and runs sphinx-build -W: warnings are errors).
project = "taskmap"
author = "taskmap contributors"
extensions = ["sphinx.ext.autodoc", "sphinx.ext.napoleon"]
napoleon_google_docstring = True
napoleon_numpy_docstring = False
napoleon_use_rtype = False
autodoc_docstring_signature = True
autodoc_member_order = "bysource"
autodoc_default_options = {"members": True, "undoc-members": False}
html_theme = "alabaster"
html_theme_options = {"nosidebar": False}
html_static_path = []
templates_path = []
exclude_patterns = []
