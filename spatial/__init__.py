"""implicad's spatial side: cells, grids, meshes, analysis, files and the command line."""
