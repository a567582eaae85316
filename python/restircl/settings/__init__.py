"""Every parameter of a render, declared once: the table (table.py: `Settings`, its choices and limits) and the
mechanism that turns a declaration into a validated field, a command-line option and a Blender property (spec.py)."""
