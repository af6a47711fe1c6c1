"""Off-screen figures, drawn from arrays (never from files); tensegrity.stages reads the files.

scene       shared VTK plumbing: off-screen plotter, colours, label style, tubes, robot,
            terrain, node numbers, robot camera, PNG writer
plot2d      2-D plots in a support frame: views, cameras, clipping, axes, labels
paper       Figs. 1/4 (robot, pairs), 5 (support frame), 6 (CoG cloud), 7 (workspace)
locomotion  Figs. 8/9 (standing, rolling), 10 (slope)
runs        the path of a run (from above, 3D) and its animation (GIF)
"""
