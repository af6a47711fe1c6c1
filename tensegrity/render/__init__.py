"""Off-screen figures, drawn from arrays (never from files); tensegrity.stages reads the files.

scene           shared VTK plumbing: off-screen plotter, colours, label style, tubes, robot,
                node numbers, robot camera, PNG writer
terrain         the terrain mesh near a point, drawn plain or coloured by height
plot2d          2-D plots in a support frame: views, cameras, clipping, labels, points
axes            their axes and scale bars, as text actors whose boxes the picture reports
paper           Figs. 1/4 (robot, pairs), 5 (support frame)
cog_cloud       Fig. 6 (CoG cloud of a sweep)
face_workspace  Fig. 7 (kinematic workspace of a face)
locomotion      Figs. 8/9 (standing, rolling), 10 (slope)
runs            the path of a run (from above, 3D)
animation       the animation of a run (GIF)
page            the interactive 3D page of the workspace and the runs (HTML, plotly)
page_traces     its pieces as plotly traces
"""
