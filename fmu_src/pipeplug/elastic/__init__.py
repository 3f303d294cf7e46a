"""Model III: elastic pipe and plug rods (grid, cells, kernels, model)."""
