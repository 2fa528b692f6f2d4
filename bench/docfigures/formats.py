"""docs/formats.md: the file formats' contract. Its numbers are the formats' limits and defaults
(fixed by the code that reads the files, checked by the tests of each reader), not
measurements: no table or prose figure comes from a result file."""

PAGE = "docs/formats.md"
TABLES: dict = {}
QUOTES: tuple = ()
