"""The study's analyses: linear analysis and controller design with python-control, the
crawler's characterisation and the position-control study's tables.

- `linear_crawler`: the crawler body's controllability (§two-mass);
- `linear_sma_thermal`: the SMA wire's thermal models and the gain-scheduled temperature PI
  (§temperature-control);
- `linear_sma_load`: the SMA bench's load path identified on its FMUs and the stress loop's PI
  (§sma-wire, §position-control);
- `linear_pneumatic`: the crawler's pressure loops identified on its FMUs and their PIs
  (§crawler-hardware, §gait);
- `linear_bending`: the bending actuator's linearised thermal and beam model, its first
  resonance and the pulse frequency the tip still follows (§bending-actuator);
- `design`: the PI designs and margins the linear analyses share;
- `characterise`: the gait's pressure references from the characterisation run (§pressure-control);
- `position`: the position-control matrix (§position-control) run as case folders
  (``musclesim.batch``) and written as tables.

Each linear analysis gives a report (a dict), its text (``format_*``) and, for the controllers,
the TOML of the gains a scenario reads (``*_toml``).
"""
from musclesim.analysis.characterise import ELONGATION_TARGET
from musclesim.analysis.characterise import references as gait_references
from musclesim.analysis.characterise import references_toml as gait_references_toml
from musclesim.analysis.linear_bending import bending, format_bending
from musclesim.analysis.linear_crawler import crawler, format_crawler
from musclesim.analysis.linear_pneumatic import format_pneumatic, pneumatic, pneumatic_gains_toml
from musclesim.analysis.linear_sma_load import format_sma_load, load_gains_toml, sma_load
from musclesim.analysis.linear_sma_thermal import format_sma_thermal, gain_table_toml, sma_thermal
from musclesim.analysis.position import sma_position

__all__ = ["crawler", "format_crawler",
           "sma_thermal", "format_sma_thermal", "gain_table_toml",
           "sma_load", "format_sma_load", "load_gains_toml",
           "pneumatic", "format_pneumatic", "pneumatic_gains_toml",
           "gait_references", "gait_references_toml", "ELONGATION_TARGET",
           "sma_position", "bending", "format_bending"]
