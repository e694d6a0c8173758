# ParaView macro: remove the mipcast volume of the active source from the active view.
# Add it with Macros > Import new macro... (needs mipcast on ParaView's Python path).
from paraview.simple import GetActiveSource, GetActiveView, Render
from mipcast.plugin.render_view import hide

hide(GetActiveSource(), GetActiveView())
Render()
