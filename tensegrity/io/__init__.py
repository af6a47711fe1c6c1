"""Every file the package reads or writes: configuration, datasets, the dataset contract."""
