"""A study: a yade-batch table of runs, checked as a whole (table_check), each
line run with the model it names (line: the FEM-DEM run of run/, or the
rigid-block model of rigid_dem/), here or on SLURM (slurm), with its folder
(folder), each line's outcome (outcome), progress on the console (progress)
and the `icerubble study` command (command). Above run/ and rigid_dem/: the
one place that picks between the two models."""
