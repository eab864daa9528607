"""softarm's tests, one folder per stage of the data path; shared helpers in `helpers`."""
