"""hapticbench's report renderer (reports/render_report.py is its command
line): inputs reads run folders and results, figures and tables draw them,
page puts them into the template."""
