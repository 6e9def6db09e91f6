#include "gui/figures/painted_file.h"

#include <QImage>
#include <QPageSize>
#include <QPainter>
#include <QPdfWriter>
#include <QSvgGenerator>
#include <stdexcept>

#include "core/atomic_file.h"

namespace linkscape::gui {

void write_painted(const std::filesystem::path& path, QSize page, const QString& title,
                   const std::function<void(QPainter&, const QRectF&)>& draw) {
  const std::string ext = path.extension().string();
  if (ext != ".png" && ext != ".svg" && ext != ".pdf")
    throw std::invalid_argument("output must end in .png, .svg or .pdf, got '" + path.string() + "'");
  write_atomically(path, [&](const std::filesystem::path& tmp) {
    const QString file = QString::fromStdString(tmp.string());
    if (ext == ".png") {
      QImage canvas(page, QImage::Format_RGB32);
      canvas.fill(Qt::white);
      QPainter p(&canvas);
      p.setRenderHint(QPainter::Antialiasing);
      draw(p, QRectF(QPointF(0, 0), QSizeF(page)));
      p.end();
      if (!canvas.save(file, "PNG")) throw std::runtime_error("cannot write '" + path.string() + "'");
    } else if (ext == ".svg") {
      QSvgGenerator svg;
      svg.setFileName(file);
      svg.setSize(page);
      svg.setViewBox(QRect(QPoint(0, 0), page));
      svg.setTitle(title);
      QPainter p(&svg);
      p.setRenderHint(QPainter::Antialiasing);
      draw(p, QRectF(QPointF(0, 0), QSizeF(page)));
    } else {
      QPdfWriter pdf(file);
      pdf.setTitle(title);
      pdf.setPageSize(QPageSize(QSizeF(page.width() * 0.75, page.height() * 0.75), QPageSize::Point));
      pdf.setPageMargins(QMarginsF(0, 0, 0, 0));
      pdf.setResolution(96);
      QPainter p(&pdf);
      p.setRenderHint(QPainter::Antialiasing);
      draw(p, QRectF(0, 0, pdf.width(), pdf.height()));
    }
  });
}

}  // namespace linkscape::gui
