"""Motion predictors for comcore (filled in by the predictors issue)."""
