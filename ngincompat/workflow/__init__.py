"""From a solved case to files: pipeline, Results, output, input files, plots, tables."""
