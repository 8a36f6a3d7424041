//! Ensembles of replicate beds: parallel runs, statistics, shards.
