"""millpath: from a part definition to verified RS274NGC (LinuxCNC) programs for 3-axis milling.

Data flow (one package per stage): part -> plan -> model.Toolpath -> fit -> post ->
G-code -> interpret -> simulate -> report.
"""

__version__ = "0.1.0"
