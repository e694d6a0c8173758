# ParaView macro: show the active source in the active render view with mipcast "demip".
# Add it with Macros > Import new macro... (needs mipcast on ParaView's Python path).
from paraview.simple import GetActiveSource, GetActiveView, Render
from mipcast.plugin.render_view import show

show(GetActiveSource(), GetActiveView(), method="demip")
Render()
