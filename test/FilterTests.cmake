# Filled in by the filter-test work.
