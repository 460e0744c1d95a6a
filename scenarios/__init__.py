"""The scenarios shipped with musclesim, installed as package data of ``musclesim.scenarios``:
the experiments' TOML files, the parameter files they read (params/) and the measured data sets
(data/). `musclesim run NAME` finds a file here by its name (`musclesim.cosim.locate_scenario`);
this package holds no code."""
