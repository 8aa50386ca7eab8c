"""Reports: report.json contents and the tool path preview picture."""
