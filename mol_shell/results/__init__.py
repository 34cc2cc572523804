"""Layer 5: labelled xarray Datasets with CF attributes; netCDF read and written atomically; stresses; study stores."""
